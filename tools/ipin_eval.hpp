#pragma once
// The IPIN competitions' scoring of a walk (../shared/data/ipin2023/README.md "How the
// competition scores a walk"; docs/ipin-import.md), for `locus eval ipin`: at each ground-truth
// instant the most recent estimate stamped at most `lag_s` after it counts; its error is the
// horizontal distance plus `floor_penalty_m` per floor of difference; a walk's (or a pool's)
// score is the 75th percentile of its errors (metrics::percentile_hazen). Pure; O(n log n).
#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

#include "locus/geometry.hpp"

namespace locus::tools::ipin {

struct Fix {
    double t = 0.0;  // seconds on the walk's clock
    int floor = 0;
    Point at;        // metres, one frame for every floor
};

struct Errors {
    std::vector<double> errors;  // one per scored instant, in truth order
    std::size_t floor_hits = 0;
    std::size_t unscored = 0;  // instants with no estimate at or before t + lag_s
};

inline constexpr double kFloorPenaltyM = 15.0;
inline constexpr double kLagS = 0.01;

// `estimates` in time order (non-decreasing t); `truth` in any order.
Errors score_instants(const std::vector<Fix>& estimates, const std::vector<Fix>& truth, double floor_penalty_m = kFloorPenaltyM,
                      double lag_s = kLagS);

// Each estimate against the truth at its own instant (the same error formula), e.g. a scan's
// answer against the scan's interpolated position: the two vectors are parallel.
Errors score_pairs(const std::vector<Fix>& estimates, const std::vector<Fix>& truth, double floor_penalty_m = kFloorPenaltyM);

// Appends b's samples to a.
void pool(Errors& a, const Errors& b);

// {"p75_m", "mean_m", "floor_hit_rate", "n", "unscored"}; nulls when nothing was scored.
nlohmann::json figures(const Errors& e);

}  // namespace locus::tools::ipin
