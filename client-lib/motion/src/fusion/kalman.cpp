#include "locus/motion/fusion/kalman.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace locus::fusion {

KalmanFilter::KalmanFilter(Point start, const KalmanConfig& config, std::shared_ptr<const PlanWalkable> floor_plan)
    : config_(config), floor_plan_(std::move(floor_plan)), x_(start.x, start.y), p_(Eigen::Matrix2d::Identity() * config.initial_sigma_m * config.initial_sigma_m) {}

void KalmanFilter::predict(Point displacement, bool magnetic_disturbance) {
    const Point from = position();
    x_ += Eigen::Vector2d(displacement.x, displacement.y);
    if (floor_plan_) {
        const Point to = config_.walls_block_steps ? floor_plan_->step(from, position()) : floor_plan_->snap(position());
        x_ = Eigen::Vector2d(to.x, to.y);
    }
    const double length = std::hypot(displacement.x, displacement.y);
    const double per_m = magnetic_disturbance ? std::max(config_.step_sigma_per_m, config_.disturbed_sigma_per_m)
                                              : config_.step_sigma_per_m;
    const double sigma = config_.step_sigma_floor_m + per_m * length;
    p_ += Eigen::Matrix2d::Identity() * sigma * sigma;
}

bool KalmanFilter::update(Point fix, const Eigen::Matrix2d& r) {
    if (floor_plan_) fix = floor_plan_->snap(fix);
    const Eigen::Vector2d innovation = Eigen::Vector2d(fix.x, fix.y) - x_;
    const Eigen::Matrix2d s = p_ + r;
    const Eigen::Matrix2d s_inv = s.inverse();
    if (config_.gate_chi2 > 0.0 && innovation.dot(s_inv * innovation) > config_.gate_chi2) return false;
    const Eigen::Matrix2d k = p_ * s_inv;
    x_ += k * innovation;
    // Joseph form keeps P symmetric positive definite under rounding.
    const Eigen::Matrix2d i_k = Eigen::Matrix2d::Identity() - k;
    p_ = i_k * p_ * i_k.transpose() + k * r * k.transpose();
    if (floor_plan_) {
        const Point snapped = floor_plan_->snap(position(), fix);
        x_ = Eigen::Vector2d(snapped.x, snapped.y);
    }
    return true;
}

Eigen::Matrix2d fix_covariance(std::span<const Point> candidates, std::span<const double> weights, double floor_m) {
    if (!weights.empty() && weights.size() != candidates.size())
        throw std::invalid_argument("fix_covariance: one weight per candidate");
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    double total = 0.0;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        const double w = weights.empty() ? 1.0 : weights[i];
        mean += w * Eigen::Vector2d(candidates[i].x, candidates[i].y);
        total += w;
    }
    if (total > 0.0) {
        mean /= total;
        for (std::size_t i = 0; i < candidates.size(); ++i) {
            const double w = weights.empty() ? 1.0 : weights[i];
            const Eigen::Vector2d d = Eigen::Vector2d(candidates[i].x, candidates[i].y) - mean;
            cov += w * d * d.transpose();
        }
        cov /= total;
    }
    const double floor2 = floor_m * floor_m;
    cov(0, 0) = std::max(cov(0, 0), floor2);
    cov(1, 1) = std::max(cov(1, 1), floor2);
    return cov;
}

}  // namespace locus::fusion
