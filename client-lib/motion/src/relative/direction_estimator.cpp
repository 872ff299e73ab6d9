#include "locus/motion/relative/direction_estimator.hpp"

#include <cmath>
#include <numbers>

namespace locus::relative {

namespace {
constexpr double kDeg = 180.0 / std::numbers::pi;
}

int weight_repeats(double w) {
    if (w < 0.5 || w > 15.0) return 0;
    if (w < 0.8) return 1;
    if (w < 1.5) return 2;
    if (w < 4.0) return 3;
    if (w < 9.0) return 4;
    return 5;
}

void DirectionEstimator::restart(Point a, double distance) {
    if (kalman_.estimate()) held_ = kalman_.estimate();
    ref_ = a;
    d0_ = distance;
    kalman_.reset();
}

StepOutcome DirectionEstimator::step(Point a, double distance) {
    a_ = a;
    dk_ = distance;
    if (!started_) {
        started_ = true;
        restart(a, distance);
        return StepOutcome::Reference;
    }
    const double dx = a.x - ref_.x, dy = a.y - ref_.y;
    const double rho = std::hypot(dx, dy);
    if (rho < params_.min_rho) return StepOutcome::TooClose;
    const double w = (d0_ - distance) / rho;
    last_weight_ = w;
    if (w > params_.max_weight) {
        restart(a, distance);
        return StepOutcome::ResetLos;
    }
    StepOutcome outcome = StepOutcome::Discarded;
    if (w >= -params_.max_weight && std::abs(w) >= params_.min_weight) {
        const double walked = std::atan2(dy, dx) * kDeg;
        const double direction = w > 0 ? walked : walked + 180.0;
        for (int i = 0; i < weight_repeats(std::abs(w)); ++i) kalman_.update(direction);
        outcome = StepOutcome::Measured;
    }
    if (distance <= params_.shrink_reset * d0_) {
        restart(a, distance);
        return StepOutcome::ResetShrunk;
    }
    return outcome;
}

std::optional<double> DirectionEstimator::direction_deg() const {
    if (kalman_.estimate()) return kalman_.estimate();
    return held_;
}

std::optional<Point> ray_circle_far(Point origin, double angle_deg, Point centre, double radius) {
    const double ux = std::cos(angle_deg / kDeg), uy = std::sin(angle_deg / kDeg);
    const double vx = origin.x - centre.x, vy = origin.y - centre.y;
    // |origin + t·u − centre|² = r²  →  t² + 2 t (u·v) + |v|² − r² = 0
    const double b = ux * vx + uy * vy;
    const double disc = b * b - (vx * vx + vy * vy) + radius * radius;
    if (disc < 0) return std::nullopt;
    const double t = -b + std::sqrt(disc);
    if (t < 0) return std::nullopt;
    return Point{origin.x + t * ux, origin.y + t * uy};
}

std::optional<Point> DirectionEstimator::target() const {
    const auto theta = direction_deg();
    if (!theta) return std::nullopt;
    if (auto p = ray_circle_far(ref_, *theta, a_, dk_)) return p;
    return Point{ref_.x + d0_ * std::cos(*theta / kDeg), ref_.y + d0_ * std::sin(*theta / kDeg)};
}

}  // namespace locus::relative
