#include "locus/fusion/ranging_fix.hpp"

#include <algorithm>
#include <cmath>

namespace locus::fusion {

Eigen::Matrix2d ranging_covariance(const ranging::Fix& fix, double floor_m) {
    const double floor2 = floor_m * floor_m;
    // An unbounded axis (transmitters in a line) becomes a large finite variance: the filter
    // then follows PDR along it.
    constexpr double kHuge = 1e6;
    Eigen::Matrix2d r;
    const double sxx = std::isfinite(fix.sxx) ? std::min(fix.sxx, kHuge) : kHuge;
    const double syy = std::isfinite(fix.syy) ? std::min(fix.syy, kHuge) : kHuge;
    const double sxy = std::isfinite(fix.sxy) ? fix.sxy : 0.0;
    r << sxx + floor2, sxy, sxy, syy + floor2;
    return r;
}

}  // namespace locus::fusion
