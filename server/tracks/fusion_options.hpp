#pragma once
// `fusion_options` on POST /v1/tracks: the Kalman methods' noise, each absent one the method's
// default (fusion::seed004_kalman_config() for kalman_seed, fusion::ranging_kalman_config()
// for kalman_ranging). Stored with the track as JSON text (migration 013). The table of
// options, which method takes each and its range, is here once: the HTTP layer validates by
// it and the filter is configured by it.
#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "tracks/fusion_method.hpp"

namespace locus::tracks {

struct FusionOptions {
    std::optional<double> r_sigma_m;      // kalman_seed: R = σ² I, whatever the fix says
    std::optional<double> q_sigma_m;      // both: Q's σ per step, however short
    std::optional<double> q_sigma_per_m;  // both: plus this σ per metre walked
    std::optional<double> r_floor_m;      // kalman_ranging: R's σ per axis is at least this
    std::optional<double> r_scale;        // kalman_ranging: the fix's covariance × this

    bool empty() const { return !r_sigma_m && !q_sigma_m && !q_sigma_per_m && !r_floor_m && !r_scale; }
};

struct FusionOptionSpec {
    const char* name;
    std::optional<double> FusionOptions::*field;
    double min, max;  // inclusive
    bool seed, ranging;  // taken by kalman_seed, by kalman_ranging
};

// Every σ is positive (a zero R or Q would make the filter trust one side absolutely), except
// the per-metre Q, which seed 004 sets to 0 (its Q is per step).
inline constexpr std::array<FusionOptionSpec, 5> kFusionOptions{{
    {"r_sigma_m", &FusionOptions::r_sigma_m, 0.05, 100.0, true, false},
    {"q_sigma_m", &FusionOptions::q_sigma_m, 0.001, 10.0, true, true},
    {"q_sigma_per_m", &FusionOptions::q_sigma_per_m, 0.0, 10.0, true, true},
    {"r_floor_m", &FusionOptions::r_floor_m, 0.01, 100.0, false, true},
    {"r_scale", &FusionOptions::r_scale, 0.01, 100.0, false, true},
}};

inline bool takes(const FusionOptionSpec& spec, FusionMethod m) {
    return (m == FusionMethod::kalman_seed && spec.seed) || (m == FusionMethod::kalman_ranging && spec.ranging);
}

// The options set, as a JSON object (as answered, and as stored: text, "" when none); unknown
// names are ignored when read back.
nlohmann::json fusion_options_json(const FusionOptions& o);
std::string fusion_options_text(const FusionOptions& o);
FusionOptions fusion_options_of_text(const std::string& text);

}  // namespace locus::tracks
