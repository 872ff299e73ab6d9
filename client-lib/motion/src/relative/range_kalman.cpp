#include "locus/motion/relative/range_kalman.hpp"

#include <algorithm>
#include <cmath>

namespace locus::relative {

namespace {
constexpr double kMinDistance = 0.05;  // m: ln d and the linearisation need d > 0
}

void RangeKalman::predict(double step_m) {
    if (!started_ || step_m <= 0) return;
    // x' = F x with F = [[1, s], [0, 1]]; P' = F P Fᵀ + Q, Q growing with the metres walked.
    d_ = std::max(kMinDistance, d_ + v_ * step_m);
    const double dd = p_dd_ + 2 * step_m * p_dv_ + step_m * step_m * p_vv_;
    const double dv = p_dv_ + step_m * p_vv_;
    p_dd_ = dd + params_.d_walk_sigma * params_.d_walk_sigma * step_m;
    p_dv_ = dv;
    p_vv_ = p_vv_ + params_.v_walk_sigma * params_.v_walk_sigma * step_m;
}

void RangeKalman::update(double innovation, double h_d, double r) {
    // H = [h_d, 0]: a measurement of d only (through ln d for RSSI).
    const double s = h_d * h_d * p_dd_ + r;
    const double k_d = p_dd_ * h_d / s, k_v = p_dv_ * h_d / s;
    d_ = std::max(kMinDistance, d_ + k_d * innovation);
    v_ = std::clamp(v_ + k_v * innovation, -1.0, 1.0);  // a rate per metre walked is a cosine
    const double dd = (1 - k_d * h_d) * p_dd_;
    const double dv = (1 - k_d * h_d) * p_dv_;
    const double vv = p_vv_ - k_v * h_d * p_dv_;
    p_dd_ = dd, p_dv_ = dv, p_vv_ = vv;
}

void RangeKalman::update_rssi(double distance_m) {
    const double z = std::log(std::max(kMinDistance, distance_m));
    if (!started_) {
        started_ = true;
        d_ = std::exp(z);
        v_ = 0;
        const double sd = params_.ln_sigma * d_;
        p_dd_ = sd * sd, p_dv_ = 0, p_vv_ = params_.v0_sigma * params_.v0_sigma;
        return;
    }
    update(z - std::log(d_), 1.0 / d_, params_.ln_sigma * params_.ln_sigma);
}

void RangeKalman::update_direct(double distance_m, double sigma_m) {
    const double z = std::max(kMinDistance, distance_m);
    if (!started_) {
        started_ = true;
        d_ = z, v_ = 0;
        p_dd_ = sigma_m * sigma_m, p_dv_ = 0, p_vv_ = params_.v0_sigma * params_.v0_sigma;
        return;
    }
    update(z - d_, 1.0, sigma_m * sigma_m);
}

std::optional<double> RangeKalman::distance() const {
    if (!started_) return std::nullopt;
    return d_;
}

}  // namespace locus::relative
