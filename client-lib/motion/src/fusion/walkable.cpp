#include "locus/motion/fusion/walkable.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace locus::fusion {

namespace {

// Rooms are unions of rectangles and may be concave (an L-shaped corridor), so "both ends
// in the room" is not enough: sample the segment every 10 cm.
bool segment_within(const Room& room, Point from, Point to) {
    const double len = distance(from, to);
    const int n = std::max(1, static_cast<int>(std::ceil(len / 0.1)));
    for (int i = 0; i <= n; ++i) {
        const double t = static_cast<double>(i) / n;
        if (!room.contains({from.x + t * (to.x - from.x), from.y + t * (to.y - from.y)})) return false;
    }
    return true;
}

}  // namespace

Walkable Walkable::from_plan(locus::plan::Plan plan) {
    Walkable w;
    w.floor_plan = std::make_shared<const PlanWalkable>(std::move(plan));
    return w;
}

bool Walkable::inside(Point p) const {
    if (floor_plan) return floor_plan->inside(p);
    return std::any_of(plan.rooms.begin(), plan.rooms.end(), [&](const Room& r) { return r.contains(p); });
}

bool Walkable::can_move(Point from, Point to) const {
    if (floor_plan) return floor_plan->can_move(from, to);
    if (!inside(to)) return false;
    if (!walls_between_rooms || !inside(from)) return true;
    for (const Room& room : plan.rooms)
        if (room.contains(from) && room.contains(to) && segment_within(room, from, to)) return true;
    return std::any_of(doors.begin(), doors.end(),
                       [&](const Segment& d) { return segments_intersect(from, to, d.a, d.b); });
}

}  // namespace locus::fusion
