#pragma once
// `locus eval walks`: real phone walks (PUTMC) through the real PDR, fixes the caller got from
// the server, and every positioning method, scored at the scans' ground-truth points. Causal
// by construction: each event (a step, a fix) happens at the time the phone would have it — a
// step when the detector confirms it, not when it was taken — and every method's estimate at
// a scan is its state right after that scan's fix. Nothing before a walk's first fix is known
// (no start point), and the map's rotation (and mirror) against the compass is learnt from
// the fixes (fusion::HeadingAlignment), never given.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "datasets/putmc.hpp"
#include "phone_steps.hpp"
#include "locus/motion/fusion/walkable.hpp"
#include "locus/motion/fusion/walk_filter.hpp"
#include "sim/evaluate.hpp"

namespace locus::tools::walks {

using tools::PhoneStep;  // tools/phone_steps.hpp

// Every step of the walk's accelerometer up to `until_s` (the phone's view at that time).
std::vector<PhoneStep> detect_steps(const datasets::putmc::Walk& walk, double until_s = INFINITY);

// The methods' parameters on real walks. Chosen on walks xperia_traj1–5 only (docs/fusion.md):
// the Kalman filter's per-metre step noise is 8× the simulator's (a real indoor compass is off
// by tens of degrees, the simulator's by a few); the five rules run with Traini 2017's exact
// constants here (Traini's λ = 4 m, N_max 10, γ 2, midpoint ½) and again tuned (below).
inline sim::EvalConfig real_walk_methods() {
    sim::EvalConfig c;
    c.kalman.step_sigma_per_m = 4.0;
    return c;
}

// The rules' parameters chosen on walks 1–5 (docs/fusion.md, "The five rules on real data"),
// reported as `<rule>_tuned` beside the rules as Traini 2017 states them.
inline fusion::RuleParams real_walk_rules() {
    fusion::RuleParams p;
    p.midpoint_wifi_weight = 0.9;  // 0.5 → 0.9 took midpoint from 3.69 to 2.29 m on walks 1–5
    p.lambda_m = 100.0;            // with that weight any λ ≤ 20 m was worse: the switch never fires
    p.n_max = 20;                  // Traini 2017's 10: every scan here has ≥ 10 APs, so α = 0 (the fix)
    p.proportional2_min_r = 0.9;   // the fix's weight at least 0.9 (6.21 → 2.29 m on walks 1–5)
    return p;
}

struct Config {
    sim::EvalConfig methods = real_walk_methods();
    fusion::RuleParams tuned_rules = real_walk_rules();
    fusion::WalkFilterConfig walk_filter = fusion::WalkFilterConfig::real_walks();  // how chosen: its comment
    bool smooth = false;  // also the offline (future-using) smoothers
    // pf_smoother's backward walk_pf: half the forward one's particles keeps the 12-walk run
    // with --smooth within 30 s (on walks 1–5: docs/fusion.md).
    int backward_particles = 1000;
};

// What one method estimated at each scan (nullopt before the walk's first fix).
struct MethodTrack {
    std::string method;
    std::vector<std::optional<Point>> at_scan;
};

struct WalkResult {
    std::string name;
    std::vector<Point> truth;  // per scan, floor frame
    std::size_t steps = 0;
    std::size_t fixes = 0;
    double offset_deg = 0.0;   // the alignment's final rotation and mirror
    bool mirrored = false;
    std::vector<MethodTrack> tracks;
    std::optional<std::pair<std::int64_t, std::string>> live_track;  // walk_pf's live track (id, token), when the caller posted one
};

// fixes[i]: the server's fix of scan i (floor frame) or nullopt when it matched nothing.
// `floor_height_m` flips PUTMC's ground truth into the floor frame (putmc::to_floor).
WalkResult evaluate_walk(const datasets::putmc::Walk& walk, const std::vector<std::optional<sim::Fix>>& fixes,
                         double floor_height_m, const std::optional<fusion::Walkable>& map, const Config& config);

// The rules that have a parameter to tune; each is also reported as `<rule>_tuned`.
std::vector<std::string_view> tuned_rule_names();
// Method names in the order of the report.
std::vector<std::string> method_names(bool with_map, bool smooth);

struct Stats {
    std::size_t n = 0;
    double mean = 0.0, median = 0.0, p75 = 0.0, p95 = 0.0;
};
Stats stats_of(std::vector<double> errors);
// The errors of `method` at the scans it has an estimate for.
std::vector<double> errors_of(const WalkResult& r, const std::string& method);

}  // namespace locus::tools::walks
