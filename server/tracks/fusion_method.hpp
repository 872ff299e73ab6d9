#pragma once
// Which filter fuses a thin client's steps on the server (`fusion` on POST /v1/tracks):
// walk_pf (fusion::WalkFilter, real-walk preset; the default), particle (the older
// fusion::ParticleFilter, which needs the floor's plan), or one of seed 004's Kalman filters
// (fusion::KalmanFilter, PDR steps as control input, a scan ranged on the floor's transmitters
// as measurement: docs/transmitters.md): kalman_seed (trilateration fixes, R and Q constant,
// fusion::seed004_kalman_config()) or kalman_ranging (multilateration fixes with their own
// covariance as R, fusion::ranging_kalman_config()), or ekf_ranging (fusion::RangingEkf, our
// tightly coupled filter: each known transmitter a scan hears is a measurement). Stored with
// the track (migrations 012, 013), so a restart or another server sharing the database keeps
// the owner's choice.
#include <optional>
#include <string>

namespace locus::tracks {

enum class FusionMethod { walk_pf, particle, kalman_seed, kalman_ranging, ekf_ranging };

inline const char* fusion_method_name(FusionMethod m) {
    switch (m) {
        case FusionMethod::walk_pf: return "walk_pf";
        case FusionMethod::particle: return "particle";
        case FusionMethod::kalman_seed: return "kalman_seed";
        case FusionMethod::kalman_ranging: return "kalman_ranging";
        case FusionMethod::ekf_ranging: return "ekf_ranging";
    }
    return "walk_pf";
}

inline std::optional<FusionMethod> fusion_method_of(const std::string& name) {
    for (const auto m : {FusionMethod::walk_pf, FusionMethod::particle, FusionMethod::kalman_seed, FusionMethod::kalman_ranging,
                           FusionMethod::ekf_ranging})
        if (name == fusion_method_name(m)) return m;
    return std::nullopt;
}

// fusion::KalmanFilter on ranged fixes.
inline bool is_kalman(FusionMethod m) { return m == FusionMethod::kalman_seed || m == FusionMethod::kalman_ranging; }
// These take a track's scans on the map's transmitters (and fusion_options); the particle
// filters match them against the radio map.
inline bool ranges_scans(FusionMethod m) { return is_kalman(m) || m == FusionMethod::ekf_ranging; }

}  // namespace locus::tracks
