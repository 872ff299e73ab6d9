#include "locus/pdr/step_detector.hpp"

#include <algorithm>
#include <cmath>

namespace locus::pdr {

// Defaults: chosen by `locus pdr tune-oxford` (grid search, leave-one-user-out) on the 48 Oxford
// optimisation traces; docs/pdr.md has the figures. Values that the search did not move keep
// the SPEC §5 figure they started from.
StepDetectorConfig::StepDetectorConfig()
    : signal(StepSignal::vertical),
      grid_hz(100.0),              // covers the step band (≤ 3 Hz) with room; 50 Hz input is interpolated
      smoothing_s(0.16),           // seed 001: 8 samples at 50 Hz
      gravity_tau_s(1.0),
      min_threshold(0.5),
      threshold_factor(0.6),
      rms_tau_s(2.0),
      hysteresis(0.5),
      min_peak_to_valley_s(0.05),
      max_peak_to_valley_s(0.6),
      min_step_interval_s(0.25),   // SPEC §5: at most one step per 250 ms
      max_gap_s(0.5) {}

StepDetector::StepDetector(const StepDetectorConfig& config) : config_(config) { reset(); }

void StepDetector::reset() {
    started_ = false;
    steps_ = 0;
    grid_dt_ = 1.0 / config_.grid_hz;
    const auto n = static_cast<std::size_t>(std::max(1.0, std::round(config_.smoothing_s * config_.grid_hz)));
    ring_.assign(n, 0.0);
    ring_pos_ = ring_fill_ = 0;
    ring_sum_ = 0.0;
    ms_ = 0.0;
    phase_ = Phase::seek_peak;
    ext_ = 0.0;
    last_step_t_ = -1e300;
    last_amplitude_ = 0.0;
}

std::optional<StepEvent> StepDetector::push(double t, double ax, double ay, double az) {
    std::optional<StepEvent> out;
    if (!started_ || t - last_t_ > config_.max_gap_s) {
        // First sample or a hole in the log: restart the filters (the step count survives).
        const auto steps = steps_;
        const double last_step = last_step_t_;
        reset();
        steps_ = steps;
        last_step_t_ = last_step;
        started_ = true;
        last_t_ = t;
        gx_ = ax, gy_ = ay, gz_ = az;
        last_s_ = 0.0;
        bin_end_ = t + grid_dt_;
        bin_area_ = 0.0;
        return out;
    }
    const double dt = t - last_t_;
    if (!(dt > 0.0)) return out;

    const double k = dt / (config_.gravity_tau_s + dt);
    gx_ += k * (ax - gx_);
    gy_ += k * (ay - gy_);
    gz_ += k * (az - gz_);
    const double gn = std::sqrt(gx_ * gx_ + gy_ * gy_ + gz_ * gz_);
    double s;
    if (config_.signal == StepSignal::vertical && gn > 1e-6)
        s = (ax * gx_ + ay * gy_ + az * gz_) / gn - gn;
    else
        s = std::sqrt(ax * ax + ay * ay + az * az) - gn;

    // Exact box average of the piecewise-linear signal over each grid bin.
    double t0 = last_t_, s0 = last_s_;
    const double slope = (s - s0) / dt;
    while (bin_end_ <= t) {
        const double s_end = s0 + slope * (bin_end_ - t0);
        bin_area_ += 0.5 * (s0 + s_end) * (bin_end_ - t0);
        on_grid_value(bin_end_, bin_area_ / grid_dt_, out);
        t0 = bin_end_;
        s0 = s_end;
        bin_area_ = 0.0;
        bin_end_ += grid_dt_;
    }
    bin_area_ += 0.5 * (s0 + s) * (t - t0);
    last_t_ = t;
    last_s_ = s;
    return out;
}

void StepDetector::on_grid_value(double t, double v, std::optional<StepEvent>& out) {
    ring_sum_ += v - ring_[ring_pos_];
    ring_[ring_pos_] = v;
    ring_pos_ = (ring_pos_ + 1) % ring_.size();
    if (ring_fill_ < ring_.size()) {
        ++ring_fill_;
        if (ring_fill_ < ring_.size()) return;
    }
    // The moving average lags by half its window; report times at the centre.
    detect(t - 0.5 * config_.smoothing_s, ring_sum_ / static_cast<double>(ring_.size()), out);
}

void StepDetector::detect(double t, double y, std::optional<StepEvent>& out) {
    const double a = grid_dt_ / (config_.rms_tau_s + grid_dt_);
    ms_ += a * (y * y - ms_);
    const double T = std::max(config_.min_threshold, config_.threshold_factor * std::sqrt(ms_));
    const double h = config_.hysteresis * T;

    if (phase_ == Phase::seek_peak) {
        if (y > ext_) ext_ = y, ext_t_ = t;
        if (ext_ > T && y < ext_ - h) {
            peak_ = ext_;
            peak_t_ = ext_t_;
            phase_ = Phase::seek_valley;
            ext_ = y;
            ext_t_ = t;
        }
        return;
    }
    // seek_valley
    if (y < ext_) ext_ = y, ext_t_ = t;
    if (ext_t_ - peak_t_ > config_.max_peak_to_valley_s) {
        // The peak found no valley in time: look for a new peak from here.
        phase_ = Phase::seek_peak;
        ext_ = y;
        ext_t_ = t;
        return;
    }
    if (y > peak_ && ext_ >= -T) {
        // A higher peak before any qualifying valley: it replaces the old one.
        phase_ = Phase::seek_peak;
        ext_ = y;
        ext_t_ = t;
        return;
    }
    if (ext_ < -T && y > ext_ + h) {
        const double dt = ext_t_ - peak_t_;
        if (dt >= config_.min_peak_to_valley_s && ext_t_ - last_step_t_ >= config_.min_step_interval_s) {
            ++steps_;
            last_step_t_ = ext_t_;
            last_amplitude_ = peak_ - ext_;
            out = StepEvent{ext_t_, peak_, ext_};
        }
        phase_ = Phase::seek_peak;
        ext_ = y;
        ext_t_ = t;
    }
}

StepEvent StepDetector::push_platform_step(double t_s) {
    ++steps_;
    last_step_t_ = t_s;
    return StepEvent{t_s, 0.5 * last_amplitude_, -0.5 * last_amplitude_};
}

}  // namespace locus::pdr
