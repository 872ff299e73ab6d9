#pragma once
// Position from steps (docs/spec.md §5.5): from a known start each step moves (length, heading)
// in the docs/spec.md §2.2 convention; after each update the room containing the position and the POIs within
// the checkpoint radius are looked up on the floor plan, if one is given. The tracker also
// carries the magnetic-disturbance flag of the heading used, so fusion can distrust it.
#include <cstdint>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/motion/pdr/step_detector.hpp"
#include "locus/motion/pdr/step_length.hpp"

namespace locus::pdr {

struct TrackPoint {
    double t_s = 0.0;
    Point position;
    double heading_rad = 0.0;
    double step_length_m = 0.0;
    bool magnetic_disturbance = false;
};

class Tracker {
public:
    // The plan, if any, must outlive the tracker.
    explicit Tracker(Point start = {}, const FloorPlan* plan = nullptr,
                     StepLengthModel model = StepLengthModel(),
                     double checkpoint_radius = kDefaultCheckpointRadius);

    TrackPoint on_step(const StepEvent& step, double heading_rad, bool magnetic_disturbance = false);
    // Moves the track without a step (a fused fix, docs/spec.md §6.8: the PDR track continues from it).
    void set_position(Point p);

    Point position() const { return position_; }
    const Room* room() const;                   // nullptr without a plan or outside every room
    std::vector<const Poi*> nearby_pois() const;
    bool magnetic_disturbance() const { return disturbed_; }
    std::uint64_t steps() const { return steps_; }
    double distance_m() const { return distance_; }
    const StepLengthModel& step_length_model() const { return model_; }
    void set_step_length_model(const StepLengthModel& m) { model_ = m; }

private:
    Point position_;
    const FloorPlan* plan_;
    StepLengthModel model_;
    double radius_;
    bool disturbed_ = false;
    std::uint64_t steps_ = 0;
    double distance_ = 0.0;
};

}  // namespace locus::pdr
