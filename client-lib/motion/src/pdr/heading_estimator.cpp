#include "locus/motion/pdr/heading_estimator.hpp"

#include <cmath>
#include <numbers>

#include "locus/motion/pdr/heading_convention.hpp"

namespace locus::pdr {

HeadingEstimator::HeadingEstimator(const HeadingConfig& config)
    : config_(config), gravity_lp_(config.input_lowpass_alpha), mag_lp_(config.input_lowpass_alpha) {
    field_norm_ = config_.expected_field_ut;
}

double HeadingEstimator::offset_rad() const {
    return config_.north_offset_deg * std::numbers::pi / 180.0 + calibration_rad_;
}

void HeadingEstimator::push_accel(double, Vec3 a) {  // time unused: the low-pass is per sample (docs/spec.md §5.4)
    gravity_lp_.push(a);
    if (mag_lp_.ready()) update_compass();
}

void HeadingEstimator::push_mag(double t_s, Vec3 m) {
    mag_lp_.push(m);
    const double n = norm(m);
    if (config_.expected_field_ut <= 0.0) {
        // Learn the local norm from the first seconds, assumed undisturbed (a calibration spot).
        if (mag_t0_ < 0.0) mag_t0_ = t_s;
        if (t_s - mag_t0_ <= config_.learn_s) {
            norm_sum_ += n;
            ++norm_n_;
            field_norm_ = norm_sum_ / static_cast<double>(norm_n_);
        }
    }
    field_bad_ = field_norm_ > 0.0 && std::abs(n - field_norm_) > config_.field_tolerance * field_norm_;
    disturbed_ = field_bad_ || disagree_;
    if (gravity_lp_.ready()) update_compass();
}

void HeadingEstimator::update_compass() {
    const auto az = compass_azimuth(gravity_lp_.value(), mag_lp_.value());
    if (!az) return;
    compass_ = *az;
    if (!theta_) theta_ = *az;
}

void HeadingEstimator::push_gyro(double t_s, Vec3 w) {
    if (!gyro_started_) {
        gyro_started_ = true;
        gyro_t_ = t_s;
        return;
    }
    const double dt = t_s - gyro_t_;
    if (!(dt > 0.0)) return;
    gyro_t_ = t_s;
    if (dt > 1.0) return;  // a hole in the log: integrating across it would invent a turn

    // Yaw rate about the vertical: ω·up is counter-clockwise seen from above, θ is clockwise.
    double turn = 0.0;
    if (gravity_lp_.ready()) {
        const Vec3 g = gravity_lp_.value();
        const double gn = norm(g);
        if (gn > 1e-6) turn = -dot(w, g) / gn * dt;
    }
    if (theta_) theta_ = wrap_angle(*theta_ + turn);

    // Gyro/compass disagreement over a sliding window of fixed length.
    if (compass_) {
        if (window_t0_ < 0.0 || !window_compass0_) {
            window_t0_ = t_s;
            window_gyro_turn_ = 0.0;
            window_compass0_ = compass_;
        } else {
            window_gyro_turn_ += turn;
            if (t_s - window_t0_ >= config_.disagreement_window_s) {
                const double compass_turn = wrap_angle(*compass_ - *window_compass0_);
                disagree_ = std::abs(wrap_angle(compass_turn - window_gyro_turn_)) > config_.disagreement_rad;
                disturbed_ = field_bad_ || disagree_;
                window_t0_ = t_s;
                window_gyro_turn_ = 0.0;
                window_compass0_ = compass_;
            }
        }
    }

    if (theta_ && compass_ && !disturbed_) {
        // Weight 0.05 per 20 ms, i.e. the same time constant at any gyro rate.
        const double w_c = 1.0 - std::pow(1.0 - config_.compass_weight, dt / 0.02);
        theta_ = wrap_angle(*theta_ + w_c * wrap_angle(*compass_ - *theta_));
    }
}

std::optional<double> HeadingEstimator::heading() const {
    if (!theta_) return std::nullopt;
    return wrap_angle(*theta_ - offset_rad());
}

void HeadingEstimator::calibrate_local_north(double known_floor_heading_rad) {
    if (!theta_) return;
    calibration_rad_ = wrap_angle(*theta_ - config_.north_offset_deg * std::numbers::pi / 180.0 -
                                  known_floor_heading_rad);
}

void HeadingEstimator::set_north_offset_deg(double deg) { config_.north_offset_deg = deg; }

void HeadingEstimator::set_heading(double floor_heading_rad) {
    theta_ = wrap_angle(floor_heading_rad + offset_rad());
}

}  // namespace locus::pdr
