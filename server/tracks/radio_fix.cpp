#include "tracks/radio_fix.hpp"

#include <algorithm>
#include <cmath>

#include "locus/motion/fusion/kalman.hpp"
#include "locus/motion/fusion/ranging_fix.hpp"

namespace locus::tracks {

Fix matched_fix(double t, std::int64_t floor_id, Point at, const std::vector<Point>& spread) {
    const Eigen::Matrix2d cov = fusion::fix_covariance(spread, {}, kScanFixFloorM);
    Fix f;
    f.t = t;
    f.floor_id = floor_id;
    f.x = at.x;
    f.y = at.y;
    f.accuracy_m = std::sqrt(cov.trace() / 2.0);  // the σ per axis of an isotropic fix with this spread
    return f;
}

std::vector<Point> candidate_spread(const match::Result& result, int k) {
    std::vector<Point> out;
    for (const auto& c : result.candidates) {
        if (static_cast<int>(out.size()) >= std::max(1, k)) break;
        out.push_back(c.at);
    }
    if (out.empty()) out.push_back(result.at);
    return out;
}

RadioFix ranged_fix(double t, std::int64_t floor_id, const ranging::Fix& fix) {
    RadioFix f;
    f.t = t;
    f.floor_id = floor_id;
    f.x = fix.at.x;
    f.y = fix.at.y;
    f.accuracy_m = std::sqrt(fusion::ranging_covariance(fix).trace() / 2.0);
    f.ranged = fix;
    return f;
}

}  // namespace locus::tracks
