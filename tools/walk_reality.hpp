#pragma once
// The statistics of real walks that the simulator is calibrated to (docs/fusion.md, "The
// simulator against the real walks"): how far the compass's rotation against the true walking
// direction wanders, how much of the distance the step detector and Weinberg length cover,
// and how WiFi fixes' errors are correlated along a walk. Measured, never eyeballed:
// `locus eval walks DIR --reality`.
#include <optional>
#include <vector>

#include "datasets/putmc.hpp"
#include "sim/evaluate.hpp"
#include "walk_eval.hpp"

namespace locus::tools::walks {

struct RealityStats {
    // Compass: the rotation φ from the PDR's to the truth's displacement between consecutive
    // scans (intervals with ≥ 2 m walked), unwrapped along the walk.
    std::size_t intervals = 0;
    double rotation_range_rad = 0.0;         // max φ − min φ within the walk
    double rotation_walk_sum_sq = 0.0;       // Σ Δφ² / metres between the intervals
    double rotation_walk_metres = 0.0;       // Σ metres (for the pooled random-walk size)
    std::size_t rotation_steps = 0;
    double rotation_walk4_sum_sq = 0.0, rotation_walk4_metres = 0.0;  // the same over 4 intervals
    bool mirrored = false;                   // the compass is mirrored against the floor
    // Distance: the steps' summed Weinberg length against the truth's polyline through the scans.
    double step_metres = 0.0, truth_metres = 0.0;
    // WiFi: error vectors of the fixes (fix − truth) at each scan, for the correlation.
    std::vector<Point> fix_error;  // nullopt fixes left out
    std::vector<Point> fix_truth;
    std::vector<double> fix_t;
};

RealityStats reality_of(const datasets::putmc::Walk& walk, const std::vector<std::optional<sim::Fix>>& fixes,
                        double floor_height_m);

// Correlation of two fixes' error vectors, Σ e_i·e_j / Σ |e|², over pairs of the same walk
// whose truths are [lo, hi) metres apart; and the pair count.
struct CorrelationBin {
    double lo = 0.0, hi = 0.0, correlation = 0.0;
    std::size_t pairs = 0;
};
std::vector<CorrelationBin> error_correlation(const std::vector<RealityStats>& walks, const std::vector<double>& edges);

}  // namespace locus::tools::walks
