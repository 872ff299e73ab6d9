#pragma once
// Two walkers for relative positioning (Bonjorn López 2016, docs/spec.md §8): B stands still, A
// starts `start_distance` away and walks to find B with no position fix, only its PDR and a
// distance to B per step. A first walks a heading within ±initial_spread of B (people roughly know
// where the other is), then follows the relative-direction estimator's bearing as soon as it has
// one (the thesis's usage: "walking towards the current estimated direction"). The score is the
// relative-direction error at every step until A is within `met_distance` of B or `seconds` have
// passed.
#include <cstdint>
#include <string>
#include <vector>

#include "locus/motion/relative/direction_estimator.hpp"
#include "locus/motion/relative/phone_rssi.hpp"
#include "locus/motion/relative/range_kalman.hpp"

namespace locus::sim {

// Where the per-step distance A–B comes from.
enum class RelativeMethod {
    Rssi,      // one RSSI reading per step through the phone-link model
    RssiMean,  // mean (in dB) of the last `rssi_window` readings
    Exact,     // the true distance: what the estimator does with perfect ranging
    RssiKalman,          // each reading through relative::RangeKalman, driven by A's PDR steps
    RssiKalmanAcoustic,  // the same, plus an acoustic range per step once within acoustic_range
    // B placed by relative::fit_target over all of A's positions and RSSI distances so far
    // (not the thesis's estimator); A follows the fit's bearing.
    RssiFit,
    // Both phones have fused fixes (the server's GET /v1/tracks/{a}/relative/{b}): the bearing
    // from A's fix to B's, each off by fix_sigma per axis; no estimator, no ranging.
    BothFixes,
};
const char* method_name(RelativeMethod m);

struct TwoWalkerConfig {
    double start_distance = 20.0;  // m
    double seconds = 30.0;
    double step_hz = 2.0;          // steps (and RSSI readings) per second
    double step_length = 0.7;      // m, true
    double step_length_sigma = 0.05;
    double heading_sigma_deg = 3.0;  // PDR heading noise per step
    double heading_bias_deg = 2.0;   // compass offset
    double initial_spread_deg = 90.0;
    // false: A keeps its first heading (walks "towards the other person" as well as it knows)
    // and only the estimate is scored, not used.
    bool follow_estimate = true;
    double shadowing_db = 4.0;       // RSSI noise
    int rssi_window = 4;
    double met_distance = 1.0;
    double acoustic_range = 1.3;    // m: the thesis's acoustic ranging works up to here...
    double acoustic_sigma = 0.01;   // ...with this error (relative_acoustic_test: within 2 cm)
    // Per-axis error of each fused fix for BothFixes, redrawn every step (fusion.md: the
    // particle filter's median error on PUTMC is about 2 m, ≈ 1.18 × σ for a 2-D Gaussian).
    double fix_sigma = 1.7;
    relative::PhoneLink link;
    relative::DirectionParams estimator;
    relative::RangeKalmanParams range_kalman;
};

struct TwoWalkerRun {
    std::vector<double> errors_deg;  // per step with an estimate
    int steps = 0;                   // steps walked
    int steps_without_estimate = 0;
    bool met = false;
    double met_after_s = 0.0;
    std::vector<double> distance_errors;  // |ranged − true| per step (m)
};

TwoWalkerRun run_two_walkers(const TwoWalkerConfig& c, RelativeMethod m, std::uint64_t seed);

struct TwoWalkerSummary {
    RelativeMethod method;
    int runs = 0;
    double median_error_deg = 0.0;
    double p90_error_deg = 0.0;
    double estimate_coverage = 0.0;  // share of steps with an estimate
    double met_share = 0.0;
    double median_met_after_s = 0.0;  // over runs that met
    double median_distance_error = 0.0;
};

// `runs` runs with seeds seed, seed+1, …; the same seeds for every method.
TwoWalkerSummary evaluate_two_walkers(const TwoWalkerConfig& c, RelativeMethod m, std::uint64_t seed, int runs);

}  // namespace locus::sim
