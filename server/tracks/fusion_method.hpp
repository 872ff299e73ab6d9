#pragma once
// Which filter fuses a thin client's steps on the server (`fusion` on POST /v1/tracks):
// walk_pf (fusion::WalkFilter, real-walk preset; the default) or particle (the older
// fusion::ParticleFilter, which needs the floor's plan). Stored with the track (migration 012),
// so a restart or another server sharing the database keeps the owner's choice.
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
