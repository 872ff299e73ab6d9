#pragma once
// Runs a walk through the real PDR pipeline and the real matcher, then through every
// positioning method on the same steps and fixes, and scores each track against the truth.
// Split in stages so `locus replay` can swap the local matcher for server fixes and reuse
// run_methods and score unchanged.
#include <Eigen/Dense>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "locus/motion/fusion/kalman.hpp"
#include "locus/motion/fusion/particle_filter.hpp"
#include "locus/motion/fusion/rules.hpp"
#include "locus/match/localize.hpp"
#include "locus/motion/pdr/pipeline.hpp"
#include "sim/walk.hpp"

namespace locus::sim {

struct PdrStep {
    double t_s = 0.0;
    double length_m = 0.0;
    double heading_rad = 0.0;
    bool magnetic_disturbance = false;  // the PDR's own flag: its heading ran on the gyro alone
};

struct Fix {
    double t_s = 0.0;
    Point at;
    int aps = 0;              // APs in the online scan (the proportional rule's N)
    Eigen::Matrix2d cov;      // from the candidate spread (fusion::fix_covariance)
};

struct TrackPoint {
    double t_s = 0.0;
    Point at;
};
using Track = std::vector<TrackPoint>;

struct NamedTrack {
    std::string method;
    Track track;
};

struct Score {
    std::string method;
    double mean_error_m = 0.0;
    double final_error_m = 0.0;
    double p95_error_m = 0.0;
    std::size_t points = 0;
};

struct EvalConfig {
    match::Algorithm algorithm = match::Algorithm::wknn;
    match::Options match_options;
    double fix_sigma_floor_m = 1.0;  // floor of the fix σ per axis (Kalman R, particle likelihood)
    // A scan's APs are heard over the channel sweep before the results arrive, so a fix
    // describes where the phone was about half a sweep earlier. The filters (not the five
    // rules) can move the fix by the PDR displacement of the steps in this last stretch
    // before using it. 0 = off. 1 s is half the simulator's 2 s sweep; per-filter choice: docs/fusion.md.
    double kalman_fix_latency_s = 0.0;
    double particle_fix_latency_s = 1.0;
    fusion::RuleParams rules;
    fusion::KalmanConfig kalman;
    fusion::ParticleConfig particle;
};

// Every IMU sample through locus::pdr::Pipeline (their step detector, Weinberg length,
// compass + gyro heading), from the walk's known start.
std::vector<PdrStep> run_pdr(const Walk& walk, pdr::PipelineConfig config = {});

// The survey scans aggregated into RPs (docs/spec.md §3.3), indexed, and every online scan matched.
match::Index build_index(const Walk& walk);
std::vector<Fix> run_matcher(const Walk& walk, const match::Index& index, const EvalConfig& config);
// One match result turned into a fix (shared with replay, which gets results from a server).
Fix make_fix(double t_s, int aps, const match::Result& result, int k, double sigma_floor_m);

// One fusion rule over the walk (the PDR continued from each fused position).
Track rule_track(fusion::Rule rule, const std::vector<PdrStep>& steps, const std::vector<Fix>& fixes, Point start,
                 const fusion::RuleParams& params);

// The fix moved by the PDR displacement of the steps taken in its last `latency_s` seconds
// (0: the fix as it is).
Point latency_corrected(const Fix& f, const std::vector<PdrStep>& steps, double latency_s);

// The Kalman filter over the walk: steps as control input, fixes (with their cov as R) as
// measurements, each first moved by latency_corrected; map-matched on a floor plan when given.
Track kalman_track(const std::vector<PdrStep>& steps, const std::vector<Fix>& fixes, Point start,
                   const fusion::KalmanConfig& config, double fix_latency_s = 0.0,
                   std::shared_ptr<const fusion::PlanWalkable> floor_plan = nullptr);

// pdr, wifi, the five rules, kalman and (with a map) particle, in the order of docs/spec.md §7.2.
// A map holding a floor plan (Walkable::from_plan) map-matches the Kalman filter too.
std::vector<NamedTrack> run_methods(const std::vector<PdrStep>& steps, const std::vector<Fix>& fixes, Point start,
                                    const std::optional<fusion::Walkable>& map, const EvalConfig& config);

// Error of every track point against the truth at its time; final = last point.
Score score(const NamedTrack& track, const Walk& walk);

std::vector<Score> evaluate(const Walk& walk, const EvalConfig& config = {});

}  // namespace locus::sim
