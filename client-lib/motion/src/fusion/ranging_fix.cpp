#include "locus/motion/fusion/ranging_fix.hpp"

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

Eigen::Matrix2d ranging_measurement_noise(const ranging::Fix& fix, const RangingKalmanConfig& config) {
    if (config.fixed_r_sigma_m > 0.0)
        return Eigen::Matrix2d::Identity() * config.fixed_r_sigma_m * config.fixed_r_sigma_m;
    // Scale first, floor after: the floor is a bound on the σ used, not on the model's.
    ranging::Fix scaled = fix;
    scaled.sxx *= config.r_scale;
    scaled.syy *= config.r_scale;
    scaled.sxy *= config.r_scale;
    return ranging_covariance(scaled, config.r_floor_m);
}

RangingKalmanConfig trilateration_kalman_config() {
    RangingKalmanConfig c;
    c.kalman.step_sigma_floor_m = 0.3;
    c.kalman.step_sigma_per_m = 0.0;
    c.fixed_r_sigma_m = 2.5;
    return c;
}

RangingKalmanConfig ranging_kalman_config() {
    RangingKalmanConfig c;
    c.kalman.step_sigma_floor_m = 0.05;
    c.kalman.step_sigma_per_m = 0.3;
    c.r_floor_m = 0.5;
    c.r_scale = 1.0;  // the fix's covariance as it is: 3 × was worse on the tuning walks
    return c;
}

}  // namespace locus::fusion
