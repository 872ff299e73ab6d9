#pragma once
// Which filter fuses a thin client's steps on the server (`fusion` on POST /v1/tracks):
// walk_pf (fusion::WalkFilter, real-walk preset; the default), particle (the older
// fusion::ParticleFilter, which needs the floor's plan), or one of the Kalman filters of the
// Kalman-fusion methodology paper (docs/spec.md §8 "Sources"; fusion::KalmanFilter, PDR steps
// as control input, a scan ranged on the floor's transmitters as measurement:
// docs/transmitters.md): kalman_trilateration (trilateration fixes, R and Q constant,
// fusion::trilateration_kalman_config()) or kalman_ranging (multilateration fixes with their
// own covariance as R, fusion::ranging_kalman_config()), or ekf_ranging (fusion::RangingEkf,
// our tightly coupled filter: each known transmitter a scan hears is a measurement). Stored
// with the track (migrations 012, 013), so a restart or another server sharing the database
// keeps the owner's choice.
//
// kalman_trilateration was first published as "kalman_seed": that name is still accepted
// wherever a method is named (a deprecated alias), and it is the one the database keeps
// (migration 013's CHECK lists it), so rows written before the rename read back unchanged.
#include <optional>
#include <string>

namespace locus::tracks {

enum class FusionMethod { walk_pf, particle, kalman_trilateration, kalman_ranging, ekf_ranging };

// The name answers and messages use.
inline const char* fusion_method_name(FusionMethod m) {
    switch (m) {
        case FusionMethod::walk_pf: return "walk_pf";
        case FusionMethod::particle: return "particle";
        case FusionMethod::kalman_trilateration: return "kalman_trilateration";
        case FusionMethod::kalman_ranging: return "kalman_ranging";
        case FusionMethod::ekf_ranging: return "ekf_ranging";
    }
    return "walk_pf";
}

// The deprecated name kalman_trilateration had before the rename (still parsed).
inline constexpr const char* kKalmanTrilaterationAlias = "kalman_seed";

// The name the tracks table keeps (its CHECK constraint predates the rename).
inline const char* fusion_method_stored_name(FusionMethod m) {
    return m == FusionMethod::kalman_trilateration ? kKalmanTrilaterationAlias : fusion_method_name(m);
}

// A method's name or its deprecated alias; nullopt for anything else.
inline std::optional<FusionMethod> fusion_method_of(const std::string& name) {
    if (name == kKalmanTrilaterationAlias) return FusionMethod::kalman_trilateration;
    for (const auto m : {FusionMethod::walk_pf, FusionMethod::particle, FusionMethod::kalman_trilateration,
                         FusionMethod::kalman_ranging, FusionMethod::ekf_ranging})
        if (name == fusion_method_name(m)) return m;
    return std::nullopt;
}

// fusion::KalmanFilter on ranged fixes.
inline bool is_kalman(FusionMethod m) { return m == FusionMethod::kalman_trilateration || m == FusionMethod::kalman_ranging; }
// These take a track's scans on the map's transmitters (and fusion_options); the particle
// filters match them against the radio map.
inline bool ranges_scans(FusionMethod m) { return is_kalman(m) || m == FusionMethod::ekf_ranging; }

}  // namespace locus::tracks
