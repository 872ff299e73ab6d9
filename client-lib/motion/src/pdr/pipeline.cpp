#include "locus/motion/pdr/pipeline.hpp"

namespace locus::pdr {

Pipeline::Pipeline(const PipelineConfig& config, const FloorPlan* plan)
    : start_heading_(config.start_heading_rad),
      steps_(config.steps),
      heading_(config.heading),
      tracker_(config.start, plan, config.step_length, config.checkpoint_radius) {}

double Pipeline::heading() const { return heading_.heading().value_or(start_heading_); }

void Pipeline::record_heading(double t_s) {
    if (history_n_ > 0) {
        const auto& last = history_[(history_head_ + history_n_ - 1) % kHistory];
        if (t_s - last.t_s < kHistoryPeriod) return;
    }
    const HeadingAt h{t_s, heading(), heading_.magnetic_disturbance()};
    if (history_n_ == kHistory) {
        history_[history_head_] = h;
        history_head_ = (history_head_ + 1) % kHistory;
    } else {
        history_[(history_head_ + history_n_++) % kHistory] = h;
    }
}

TrackPoint Pipeline::step(const StepEvent& e) {
    double h = heading();
    bool disturbed = heading_.magnetic_disturbance();
    // Newest record not after the step; steps older than the history take the oldest.
    for (std::size_t i = history_n_; i-- > 0;) {
        const auto& r = history_[(history_head_ + i) % kHistory];
        if (r.t_s <= e.t_s || i == 0) {
            h = r.heading;
            disturbed = r.disturbed;
            break;
        }
    }
    return tracker_.on_step(e, h, disturbed);
}

std::optional<TrackPoint> Pipeline::push_accel(double t_s, Vec3 a) {
    heading_.push_accel(t_s, a);
    record_heading(t_s);
    if (auto e = steps_.push(t_s, a.x, a.y, a.z)) return step(*e);
    return std::nullopt;
}

std::optional<TrackPoint> Pipeline::poll() {
    if (auto e = steps_.poll()) return step(*e);
    return std::nullopt;
}

void Pipeline::push_gyro(double t_s, Vec3 w) { heading_.push_gyro(t_s, w); }
void Pipeline::push_mag(double t_s, Vec3 m) { heading_.push_mag(t_s, m); }

TrackPoint Pipeline::push_platform_step(double t_s) {
    // Platform events arrive when they happen: the current heading is the right one.
    return tracker_.on_step(steps_.push_platform_step(t_s), heading(), heading_.magnetic_disturbance());
}

}  // namespace locus::pdr
