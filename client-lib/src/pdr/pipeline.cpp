#include "locus/pdr/pipeline.hpp"

namespace locus::pdr {

Pipeline::Pipeline(const PipelineConfig& config, const FloorPlan* plan)
    : start_heading_(config.start_heading_rad),
      steps_(config.steps),
      heading_(config.heading),
      tracker_(config.start, plan, config.step_length, config.checkpoint_radius) {}

double Pipeline::heading() const { return heading_.heading().value_or(start_heading_); }

TrackPoint Pipeline::step(const StepEvent& e) {
    return tracker_.on_step(e, heading(), heading_.magnetic_disturbance());
}

std::optional<TrackPoint> Pipeline::push_accel(double t_s, Vec3 a) {
    heading_.push_accel(t_s, a);
    if (auto e = steps_.push(t_s, a.x, a.y, a.z)) return step(*e);
    return std::nullopt;
}

std::optional<TrackPoint> Pipeline::poll() {
    if (auto e = steps_.poll()) return step(*e);
    return std::nullopt;
}

void Pipeline::push_gyro(double t_s, Vec3 w) { heading_.push_gyro(t_s, w); }
void Pipeline::push_mag(double t_s, Vec3 m) { heading_.push_mag(t_s, m); }

TrackPoint Pipeline::push_platform_step(double t_s) { return step(steps_.push_platform_step(t_s)); }

}  // namespace locus::pdr
