#include "locus/motion/pdr/step_detector.hpp"

#include <algorithm>
#include <cmath>

namespace locus::pdr {

StepDetectorConfig::StepDetectorConfig()
    : signal(kDefaultSignal),
      grid_hz(kDefaultGridHz),
      smoothing_s(kDefaultSmoothingS),
      gravity_tau_s(kDefaultGravityTauS),
      min_threshold(kDefaultMinThreshold),
      threshold_factor(kDefaultThresholdFactor),
      rms_tau_s(kDefaultRmsTauS),
      hysteresis(kDefaultHysteresis),
      min_peak_to_valley_s(kDefaultMinPeakToValleyS),
      max_peak_to_valley_s(kDefaultMaxPeakToValleyS),
      min_step_interval_s(kDefaultMinStepIntervalS),
      max_gap_s(kDefaultMaxGapS),
      bout_steps(kDefaultBoutSteps),
      bout_regularity(kDefaultBoutRegularity),
      cadence_min_ratio(kDefaultCadenceMinRatio),
      cadence_max_ratio(kDefaultCadenceMaxRatio),
      max_step_interval_s(kDefaultMaxStepIntervalS) {}

StepDetector::StepDetector(const StepDetectorConfig& config) : config_(config) {
    config_.bout_steps = std::clamp(config_.bout_steps, 0, static_cast<int>(kMaxBout));
    reset();
}

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
    last_candidate_t_ = -1e300;
    last_amplitude_ = 0.0;
    walking_ = false;
    bout_n_ = 0;
    last_step_t_ = prev_step_t_ = -1e300;
    intervals_n_ = intervals_pos_ = 0;
    due_head_ = due_n_ = 0;
}

std::optional<StepEvent> StepDetector::poll() {
    if (due_n_ == 0) return std::nullopt;
    const StepEvent e = due_[due_head_];
    due_head_ = (due_head_ + 1) % std::size(due_);
    --due_n_;
    return e;
}

std::optional<StepEvent> StepDetector::push(double t, double ax, double ay, double az) {
    if (!started_ || t - last_t_ > config_.max_gap_s) {
        // First sample or a hole in the log: restart the signal filters; the step count, the
        // cadence state and the steps due survive.
        started_ = true;
        last_t_ = t;
        gx_ = ax, gy_ = ay, gz_ = az;
        last_s_ = 0.0;
        bin_end_ = t + grid_dt_;
        bin_area_ = 0.0;
        std::fill(ring_.begin(), ring_.end(), 0.0);
        ring_pos_ = ring_fill_ = 0;
        ring_sum_ = 0.0;
        phase_ = Phase::seek_peak;
        ext_ = 0.0;
        return poll();
    }
    const double dt = t - last_t_;
    if (!(dt > 0.0)) return poll();

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
        on_grid_value(bin_end_, bin_area_ / grid_dt_);
        t0 = bin_end_;
        s0 = s_end;
        bin_area_ = 0.0;
        bin_end_ += grid_dt_;
    }
    bin_area_ += 0.5 * (s0 + s) * (t - t0);
    last_t_ = t;
    last_s_ = s;
    return poll();
}

void StepDetector::on_grid_value(double t, double v) {
    ring_sum_ += v - ring_[ring_pos_];
    ring_[ring_pos_] = v;
    ring_pos_ = (ring_pos_ + 1) % ring_.size();
    if (ring_fill_ < ring_.size()) {
        ++ring_fill_;
        if (ring_fill_ < ring_.size()) return;
    }
    // The moving average lags by half its window; report times at the centre.
    detect(t - 0.5 * config_.smoothing_s, ring_sum_ / static_cast<double>(ring_.size()));
}

void StepDetector::detect(double t, double y) {
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
    if (y < ext_) ext_ = y, ext_t_ = t;
    if (ext_t_ - peak_t_ > config_.max_peak_to_valley_s) {
        // The peak found no valley in time: look for a new peak from here.
        phase_ = Phase::seek_peak;
        ext_ = y;
        ext_t_ = t;
        return;
    }
    if (y > peak_ && ext_ >= -T) {
        // A higher peak before any qualifying valley replaces the old one.
        phase_ = Phase::seek_peak;
        ext_ = y;
        ext_t_ = t;
        return;
    }
    if (ext_ < -T && y > ext_ + h) {
        if (ext_t_ - peak_t_ >= config_.min_peak_to_valley_s &&
            ext_t_ - last_candidate_t_ >= config_.min_step_interval_s) {
            last_candidate_t_ = ext_t_;
            last_amplitude_ = peak_ - ext_;
            candidate(StepEvent{ext_t_, peak_, ext_});
        }
        phase_ = Phase::seek_peak;
        ext_ = y;
        ext_t_ = t;
    }
}

// Cadence is measured per stride (two steps), not per step: with the phone in a front pocket the
// detected instant differs between the two legs, so step intervals alternate (e.g. 0.37/0.69 s)
// while strides stay regular.
double StepDetector::cadence() const {
    double v[kCadenceHistory];
    std::copy(intervals_, intervals_ + intervals_n_, v);
    std::nth_element(v, v + intervals_n_ / 2, v + intervals_n_);
    return v[intervals_n_ / 2];
}

void StepDetector::confirm(const StepEvent& e) {
    if (prev_step_t_ > -1e299 && e.t_s - prev_step_t_ <= 2.0 * config_.max_step_interval_s) {
        intervals_[intervals_pos_] = e.t_s - prev_step_t_;
        intervals_pos_ = (intervals_pos_ + 1) % kCadenceHistory;
        intervals_n_ = std::min(intervals_n_ + 1, kCadenceHistory);
    }
    prev_step_t_ = last_step_t_;
    last_step_t_ = e.t_s;
    ++steps_;
    const std::size_t cap = std::size(due_);
    if (due_n_ == cap) {  // nobody is draining: keep the newest, the count is kept anyway
        due_head_ = (due_head_ + 1) % cap;
        --due_n_;
    }
    due_[(due_head_ + due_n_) % cap] = e;
    ++due_n_;
}

void StepDetector::candidate(const StepEvent& e) {
    if (config_.bout_steps <= 1) {
        confirm(e);
        return;
    }
    if (walking_) {
        const double stride = e.t_s - prev_step_t_;
        const double c = cadence();
        if (stride < config_.cadence_min_ratio * c) return;  // a second bump within one step
        if (stride <= config_.cadence_max_ratio * c && e.t_s - last_step_t_ <= config_.max_step_interval_s) {
            confirm(e);
            return;
        }
        walking_ = false;  // a pause or a break in rhythm: the next bout must prove itself
        bout_n_ = 0;
    }
    if (bout_n_ > 0 && e.t_s - bout_[bout_n_ - 1].t_s > config_.max_step_interval_s) bout_n_ = 0;
    bout_[bout_n_++] = e;
    // Drop the oldest candidates until the strides left are regular.
    for (;;) {
        double lo = 1e300, hi = 0.0;
        for (std::size_t i = 2; i < bout_n_; ++i) {
            const double d = bout_[i].t_s - bout_[i - 2].t_s;
            lo = std::min(lo, d);
            hi = std::max(hi, d);
        }
        if (bout_n_ < 4 || hi <= config_.bout_regularity * lo) break;
        std::copy(bout_ + 1, bout_ + bout_n_, bout_);
        --bout_n_;
    }
    if (bout_n_ >= static_cast<std::size_t>(config_.bout_steps)) {
        walking_ = true;
        intervals_n_ = intervals_pos_ = 0;
        last_step_t_ = prev_step_t_ = -1e300;
        for (std::size_t i = 0; i < bout_n_; ++i) confirm(bout_[i]);
        bout_n_ = 0;
    }
}

StepEvent StepDetector::push_platform_step(double t_s) {
    ++steps_;
    return StepEvent{t_s, 0.5 * last_amplitude_, -0.5 * last_amplitude_};
}

}  // namespace locus::pdr
