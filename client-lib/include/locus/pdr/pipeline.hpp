#pragma once
// The whole PDR chain behind one streaming interface: accelerometer → StepDetector, all three
// sensors → HeadingEstimator, each step → Tracker. What an app (or the simulator) feeds.
#include <optional>

#include "locus/pdr/heading_estimator.hpp"
#include "locus/pdr/step_detector.hpp"
#include "locus/pdr/tracker.hpp"

namespace locus::pdr {

struct PipelineConfig {
    StepDetectorConfig steps;
    HeadingConfig heading;
    StepLengthModel step_length;
    Point start;
    double start_heading_rad = 0.0;  // used until the compass gives a heading
    double checkpoint_radius = kDefaultCheckpointRadius;
};

class Pipeline {
public:
    explicit Pipeline(const PipelineConfig& config = PipelineConfig(), const FloorPlan* plan = nullptr);

    // Returns the new track point when the sample completed a step.
    std::optional<TrackPoint> push_accel(double t_s, Vec3 a);
    // Steps confirmed but not yet returned (a bout confirms several at once); call at the end.
    std::optional<TrackPoint> poll();
    void push_gyro(double t_s, Vec3 w);
    void push_mag(double t_s, Vec3 m);
    // Platform step events instead of accelerometer-detected ones.
    TrackPoint push_platform_step(double t_s);

    double heading() const;
    StepDetector& step_detector() { return steps_; }
    HeadingEstimator& heading_estimator() { return heading_; }
    Tracker& tracker() { return tracker_; }
    const Tracker& tracker() const { return tracker_; }

private:
    TrackPoint step(const StepEvent& e);

    double start_heading_;
    StepDetector steps_;
    HeadingEstimator heading_;
    Tracker tracker_;
};

}  // namespace locus::pdr
