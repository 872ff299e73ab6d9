#include "locus/motion/pdr/tracker.hpp"

#include "locus/motion/pdr/heading_convention.hpp"

namespace locus::pdr {

Tracker::Tracker(Point start, const FloorPlan* plan, StepLengthModel model, double checkpoint_radius)
    : position_(start), plan_(plan), model_(model), radius_(checkpoint_radius) {}

TrackPoint Tracker::on_step(const StepEvent& e, double heading_rad, bool magnetic_disturbance) {
    const double len = model_.length(e);
    position_ = step(position_, len, heading_rad);
    disturbed_ = magnetic_disturbance;
    ++steps_;
    distance_ += len;
    return TrackPoint{e.t_s, position_, heading_rad, len, magnetic_disturbance};
}

void Tracker::set_position(Point p) { position_ = p; }

const Room* Tracker::room() const { return plan_ ? plan_->room_at(position_) : nullptr; }

std::vector<const Poi*> Tracker::nearby_pois() const {
    return plan_ ? plan_->pois_near(position_, radius_) : std::vector<const Poi*>{};
}

}  // namespace locus::pdr
