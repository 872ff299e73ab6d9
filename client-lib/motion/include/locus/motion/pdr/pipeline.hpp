#pragma once
// The whole PDR chain behind one streaming interface: accelerometer → StepDetector, all three
// sensors → HeadingEstimator, each step → Tracker. What an app (or the simulator) feeds.
// The step detector confirms the first steps of a walking bout a few seconds late; each step is
// placed with the heading (and disturbance flag) recorded at its own time, kept every 0.1 s for
// the last 12.8 s, so a turn made while a bout was being confirmed bends the track correctly.
#include <cstddef>
#include <optional>

#include "locus/motion/pdr/heading_estimator.hpp"
#include "locus/motion/pdr/step_detector.hpp"
#include "locus/motion/pdr/tracker.hpp"

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
    void record_heading(double t_s);

    struct HeadingAt {
        double t_s;
        double heading;
        bool disturbed;
    };
    static constexpr std::size_t kHistory = 128;
    static constexpr double kHistoryPeriod = 0.1;
    HeadingAt history_[kHistory];
    std::size_t history_head_ = 0;  // index of the oldest entry
    std::size_t history_n_ = 0;

    double start_heading_;
    StepDetector steps_;
    HeadingEstimator heading_;
    Tracker tracker_;
};

}  // namespace locus::pdr
