#include "locus/motion/fusion/ranging_ekf.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace locus::fusion {

RangingEkf::RangingEkf(Point start, std::span<const RangingAnchor> anchors, const RangingEkfConfig& config)
    : config_(config) {
    // A zero σ or Huber threshold divides by zero in the update and turns the state NaN.
    if (!(config.reading_sigma_db > 0.0) || !(config.huber_k > 0.0) || !(config.min_range_m > 0.0) || config.iterations < 1)
        throw std::invalid_argument("RangingEkfConfig: reading_sigma_db, huber_k and min_range_m must be positive and iterations at least 1");
    for (const RangingAnchor& a : anchors) anchors_[a.id] = a.tx;
    s_ << start.x, start.y, 0.0, 0.0;
    p_.setZero();
    p_(0, 0) = p_(1, 1) = config_.initial_sigma_m * config_.initial_sigma_m;
    p_(2, 2) = config_.offset_sigma_db * config_.offset_sigma_db;
    if (config_.estimate_heading_bias) p_(3, 3) = config_.heading_bias_sigma_rad * config_.heading_bias_sigma_rad;
}

void RangingEkf::advance_time(double t_s) {
    if (has_time_ && t_s > t_s_) {
        const double w = config_.offset_walk_db_per_sqrt_s;
        p_(2, 2) += w * w * (t_s - t_s_);
    }
    if (!has_time_ || t_s > t_s_) t_s_ = t_s;
    has_time_ = true;
}

void RangingEkf::predict(Point displacement, double t_s) {
    advance_time(t_s);
    const double c = std::cos(s_(3)), s = std::sin(s_(3));
    const double ux = c * displacement.x - s * displacement.y;
    const double uy = s * displacement.x + c * displacement.y;
    s_(0) += ux;
    s_(1) += uy;
    if (config_.step_lead_s > 0.0) {
        recent_steps_.emplace_back(t_s, Eigen::Vector2d(ux, uy));
        while (!recent_steps_.empty() && recent_steps_.front().first <= t_s - config_.step_lead_s)
            recent_steps_.pop_front();
    }
    const double len = std::hypot(displacement.x, displacement.y);
    Eigen::Matrix4d f = Eigen::Matrix4d::Identity();
    if (config_.estimate_heading_bias) {
        // ∂(R(β)u)/∂β: the displacement turned a quarter further.
        f(0, 3) = -uy;
        f(1, 3) = ux;
    }
    p_ = f * p_ * f.transpose();
    const double q = config_.step_sigma_floor_m + config_.step_sigma_per_m * len;
    p_(0, 0) += q * q;
    p_(1, 1) += q * q;
    const double hw = config_.heading_walk_rad_per_sqrt_m;
    if (config_.estimate_heading_bias) p_(3, 3) += hw * hw * len;
}

Eigen::Vector2d RangingEkf::moved_since(double t_s) const {
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    for (const auto& [t, u] : recent_steps_)
        if (t > t_s - config_.step_lead_s) d += u;
    return d;
}

int RangingEkf::update(std::span<const AnchorReading> readings) {
    std::vector<const ranging::Transmitter*> tx;
    std::vector<double> z;
    std::vector<Eigen::Vector2d> back;  // per reading: the steps stamped since it
    tx.reserve(readings.size());
    back.reserve(readings.size());
    z.reserve(readings.size());
    double latest = t_s_;
    for (const AnchorReading& r : readings) {
        const auto it = anchors_.find(r.anchor_id);
        if (it == anchors_.end() || !std::isfinite(r.rss)) continue;
        tx.push_back(&it->second);
        z.push_back(r.rss);
        back.push_back(moved_since(r.t_s));
        latest = std::max(latest, r.t_s);
    }
    const int m = static_cast<int>(tx.size());
    if (m == 0) return 0;
    advance_time(latest);

    const double sigma = config_.reading_sigma_db;
    const double k10 = 10.0 / std::numbers::ln10;
    const double min_h2 = config_.min_range_m * config_.min_range_m;
    const Eigen::Vector4d s0 = s_;
    Eigen::Vector4d si = s0;
    Eigen::MatrixXd h(m, 4);
    Eigen::VectorXd r(m), rv(m);
    Eigen::MatrixXd k;
    const int iterations = std::max(1, config_.iterations);
    for (int it = 0; it < iterations; ++it) {
        for (int j = 0; j < m; ++j) {
            const ranging::Transmitter& t = *tx[static_cast<std::size_t>(j)];
            const Eigen::Vector2d& b = back[static_cast<std::size_t>(j)];
            const double dx = si(0) - b.x() - t.at.x, dy = si(1) - b.y() - t.at.y;
            const double d2 = std::max(dx * dx + dy * dy, min_h2) + t.dz * t.dz;
            const double n = t.model.exponent;
            const double predicted = ranging::rss_at(t.model, std::sqrt(d2)) + si(2);
            h(j, 0) = -k10 * n * dx / d2;
            h(j, 1) = -k10 * n * dy / d2;
            h(j, 2) = 1.0;
            h(j, 3) = 0.0;
            const double e = z[static_cast<std::size_t>(j)] - predicted;
            // Iterated EKF: the innovation linearised at si, taken back to the prior s0.
            r(j) = e - h.row(j).dot(s0 - si);
            const double a = std::abs(e) / (config_.huber_k * sigma);
            rv(j) = sigma * sigma * std::max(1.0, a);
        }
        const Eigen::MatrixXd ph = p_ * h.transpose();
        Eigen::MatrixXd s = h * ph;
        s.diagonal() += rv;
        k = ph * s.ldlt().solve(Eigen::MatrixXd::Identity(m, m));
        const Eigen::Vector4d next = s0 + k * r;
        const bool converged = (next.head<2>() - si.head<2>()).norm() < 1e-3;
        si = next;
        if (converged) break;
    }
    // Joseph form: stays symmetric and positive with the Huber-inflated R.
    const Eigen::Matrix4d ikh = Eigen::Matrix4d::Identity() - k * h;
    p_ = ikh * p_ * ikh.transpose() + k * rv.asDiagonal() * k.transpose();
    s_ = si;
    return m;
}

void RangingEkf::update_position(Point at, const Eigen::Matrix2d& r) {
    Eigen::Matrix<double, 2, 4> h = Eigen::Matrix<double, 2, 4>::Zero();
    h(0, 0) = h(1, 1) = 1.0;
    const Eigen::Matrix2d s = h * p_ * h.transpose() + r;
    const Eigen::Matrix<double, 4, 2> k = p_ * h.transpose() * s.inverse();
    s_ += k * (Eigen::Vector2d(at.x, at.y) - s_.head<2>());
    const Eigen::Matrix4d ikh = Eigen::Matrix4d::Identity() - k * h;
    p_ = ikh * p_ * ikh.transpose() + k * r * k.transpose();
}

}  // namespace locus::fusion
