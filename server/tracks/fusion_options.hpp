#pragma once
// `fusion_options` on POST /v1/tracks: the Kalman methods' noise and walk_pf's priors, each absent
// one the method's default (fusion::trilateration_kalman_config() for kalman_trilateration,
// fusion::ranging_kalman_config() for kalman_ranging, fusion::RangingEkfConfig{} for ekf_ranging,
// fusion::WalkFilterConfig::real_walks() for walk_pf).
// Stored with the track as JSON text (migration 013). The table of options, which method takes each
// and its range, is here once: the HTTP layer validates by it and the filter is configured by it.
#include <array>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>

#include "tracks/fusion_method.hpp"

namespace locus::tracks {

struct FusionOptions {
    std::optional<double> r_sigma_m;      // kalman_trilateration: R = σ² I, whatever the fix says
    std::optional<double> q_sigma_m;      // all three: Q's σ per step, however short
    std::optional<double> q_sigma_per_m;  // all three: plus this σ per metre walked
    std::optional<double> r_floor_m;      // kalman_ranging: R's σ per axis is at least this
    std::optional<double> r_scale;        // kalman_ranging: the fix's covariance × this
    // ekf_ranging (fusion::RangingEkfConfig's fields of the same meaning):
    std::optional<double> reading_sigma_db;            // σ of one reading about the path-loss model
    std::optional<double> step_lead_s;                 // how far the PDR's step stamps lead the motion
    std::optional<double> offset_sigma_db;             // prior σ of the phone's RSS offset
    std::optional<double> heading_walk_rad_per_sqrt_m; // the compass drift's random walk
    std::optional<double> huber_k;                     // readings beyond this many σ are down-weighted
    // walk_pf (fusion::WalkFilterConfig's fields; the defaults are WalkFilterConfig::real_walks(),
    // chosen on the PUTMC walks): a phone whose detected steps are near their true length, or
    // a radio map whose answers are off by more (the IPIN 2023 walks, docs/results.md), tracks
    // better with its own.
    std::optional<double> step_scale;                  // the prior mean of the steps' scale
    std::optional<double> step_scale_sigma;            // and its σ
    std::optional<double> fix_sigma_m;                 // a radio fix's σ is at least this
    std::optional<double> reseed_fraction;             // the share of the cloud re-drawn round a fix...
    std::optional<double> reseed_max_fraction;         // ...rising to this one when the fix surprises it
    // The steps' headings are already the floor's to within this σ (a compass azimuth less the
    // floor's georeferenced bearing): the compass's rotation is drawn round 0, not learnt.
    std::optional<double> rotation_sigma_deg;
    std::optional<double> rotation_walk_deg;           // the rotation's random walk per step (the compass's drift)
    // walk_pf: false matches every scan on the whole map instead of round the filter's estimate
    // (the dynamic subarea, docs/tracks.md "Subarea"; on when absent). Not a number, so not in
    // kFusionOptions: read and written beside it.
    std::optional<bool> subarea;

    bool empty() const;
};

struct FusionOptionSpec {
    const char* name;
    std::optional<double> FusionOptions::*field;
    double min, max;  // inclusive
    bool trilateration, ranging, ekf;  // taken by kalman_trilateration, by kalman_ranging, by ekf_ranging
    bool walk = false;                 // taken by walk_pf
};

// Every σ is positive (a zero R or Q would make the filter trust one side absolutely), except the
// per-metre Q, which the Kalman-fusion paper sets to 0 (its Q is per step), and the EKF's step lead
// (0 turns it off), offset σ (0: the phone's offset is held at 0) and heading walk (0: the bias
// stays at what the first readings make of it).
inline constexpr std::array<FusionOptionSpec, 17> kFusionOptions{{
    {"r_sigma_m", &FusionOptions::r_sigma_m, 0.05, 100.0, true, false, false},
    {"q_sigma_m", &FusionOptions::q_sigma_m, 0.001, 10.0, true, true, true},
    {"q_sigma_per_m", &FusionOptions::q_sigma_per_m, 0.0, 10.0, true, true, true},
    {"r_floor_m", &FusionOptions::r_floor_m, 0.01, 100.0, false, true, false},
    {"r_scale", &FusionOptions::r_scale, 0.01, 100.0, false, true, false},
    {"reading_sigma_db", &FusionOptions::reading_sigma_db, 0.1, 30.0, false, false, true},
    {"step_lead_s", &FusionOptions::step_lead_s, 0.0, 5.0, false, false, true},
    {"offset_sigma_db", &FusionOptions::offset_sigma_db, 0.0, 30.0, false, false, true},
    {"heading_walk_rad_per_sqrt_m", &FusionOptions::heading_walk_rad_per_sqrt_m, 0.0, 1.0, false, false, true},
    {"huber_k", &FusionOptions::huber_k, 0.5, 100.0, false, false, true},
    {"step_scale", &FusionOptions::step_scale, 0.2, 5.0, false, false, false, true},
    {"step_scale_sigma", &FusionOptions::step_scale_sigma, 0.01, 2.0, false, false, false, true},
    {"fix_sigma_m", &FusionOptions::fix_sigma_m, 0.1, 100.0, false, false, false, true},
    {"reseed_fraction", &FusionOptions::reseed_fraction, 0.0, 1.0, false, false, false, true},
    {"reseed_max_fraction", &FusionOptions::reseed_max_fraction, 0.0, 1.0, false, false, false, true},
    {"rotation_sigma_deg", &FusionOptions::rotation_sigma_deg, 0.1, 90.0, false, false, false, true},
    {"rotation_walk_deg", &FusionOptions::rotation_walk_deg, 0.0, 30.0, false, false, false, true},
}};

inline bool takes(const FusionOptionSpec& spec, FusionMethod m) {
    return (m == FusionMethod::kalman_trilateration && spec.trilateration) || (m == FusionMethod::kalman_ranging && spec.ranging) ||
           (m == FusionMethod::ekf_ranging && spec.ekf) || (m == FusionMethod::walk_pf && spec.walk);
}

inline constexpr const char* kSubareaOption = "subarea";

// The options set, as a JSON object (as answered, and as stored: text, "" when none); unknown
// names are ignored when read back.
nlohmann::json fusion_options_json(const FusionOptions& o);
std::string fusion_options_text(const FusionOptions& o);
FusionOptions fusion_options_of_text(const std::string& text);

}  // namespace locus::tracks
