#pragma once
// locus_datasets (datasets/): the data set and file readers, a library apart from the CLI so that
// tests, benchmarks and fuzz targets read a file exactly as the commands do.
//
// The Oxford step-counter optimisation set (Brajdic & Harle, CC BY 4.0) for `locus pdr
// eval-oxford` and `tune-oxford`: loading, counting steps and leave-one-user-out tuning.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "datasets/pdr_logs.hpp"
#include "locus/motion/pdr/step_detector.hpp"

namespace locus::datasets {

struct OxfordTrace {
    std::string name;
    std::string user;
    std::string phone;
    std::string placement;  // canonical spelling (the data set writes ArmBand/Armband, Backpocket/BackPocket)
    long true_steps = 0;       // stats.csv: the official figure every error here is against
    // Foot-switch transitions (stepcounter.csv) counted only when ≥ 0.35 s after the previous
    // counted one: some traces (the arm ones especially) have switch bounces 0.2–0.3 s apart
    // that no walking cadence explains. Reported beside the official error, never tuned on.
    long debounced_steps = 0;
    // Foot-switch rises counted only when the foot differs from the previous rise's: one foot
    // cannot land twice without the other landing in between, so a same-foot repeat is a bounce.
    // Parameter-free cross-check of the debounced figure (they agree within 1 step on both
    // swinging-arm traces); reported, never tuned on.
    long alternating_steps = 0;
    std::vector<AccelSample> samples;
};

// `dir` is the optimisation folder (holding stats.csv and data/) or its parent.
std::vector<OxfordTrace> load_oxford(const std::string& dir);

long count_steps(const std::vector<AccelSample>& samples, const pdr::StepDetectorConfig& config);

struct TraceResult {
    const OxfordTrace* trace;
    long detected;
    double abs_error_pct;
};

struct EvalSummary {
    std::vector<TraceResult> traces;
    double mean_abs_error_pct = 0.0;
    std::map<std::string, double> placement_mean_pct;
    double worst_placement_pct = 0.0;
};

EvalSummary evaluate(const std::vector<const OxfordTrace*>& traces, const pdr::StepDetectorConfig& config);
EvalSummary summarise(std::vector<TraceResult> results);

// The tuning objective: the mean absolute error over traces, the headline figure (docs/spec.md §7.3;
// an objective tried and dropped: docs/pdr.md).
double objective(const EvalSummary& s);

std::vector<pdr::StepDetectorConfig> tuning_grid();

struct CvResult {
    EvalSummary held_out;                            // each trace scored with the config tuned without its user
    std::map<std::string, pdr::StepDetectorConfig> chosen;  // per held-out user
    pdr::StepDetectorConfig all_traces_best;
    EvalSummary all_traces_fit;
};

// Scores every grid config on every trace once (threads workers), then picks per fold.
CvResult tune_leave_one_user_out(const std::vector<OxfordTrace>& traces, const std::vector<pdr::StepDetectorConfig>& grid,
                                 unsigned threads, const std::function<void(std::size_t, std::size_t)>& progress);

}  // namespace locus::datasets
