#pragma once
// Which filter fuses a thin client's steps on the server (`fusion` on POST /v1/tracks):
// walk_pf (fusion::WalkFilter, real-walk preset; the default) or particle (the older
// fusion::ParticleFilter, which needs the floor's plan). Kept in memory with the track: the
// tracks table (migration 008) has no column for it, so after a restart a track runs walk_pf.
#include <optional>
#include <string>

namespace locus::tracks {

enum class FusionMethod { walk_pf, particle };

inline const char* fusion_method_name(FusionMethod m) { return m == FusionMethod::particle ? "particle" : "walk_pf"; }

inline std::optional<FusionMethod> fusion_method_of(const std::string& name) {
    if (name == "walk_pf") return FusionMethod::walk_pf;
    if (name == "particle") return FusionMethod::particle;
    return std::nullopt;
}

}  // namespace locus::tracks
