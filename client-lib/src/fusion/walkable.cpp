#include "locus/fusion/walkable.hpp"

#include <algorithm>
#include <cmath>

namespace locus::fusion {

namespace {

double cross(Point o, Point a, Point b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

bool on_segment(Point p, Point a, Point b) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

int sign(double v) { return (v > 0.0) - (v < 0.0); }

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

bool segments_intersect(Point p, Point q, Point a, Point b) {
    const int d1 = sign(cross(a, b, p));
    const int d2 = sign(cross(a, b, q));
    const int d3 = sign(cross(p, q, a));
    const int d4 = sign(cross(p, q, b));
    if (d1 * d2 < 0 && d3 * d4 < 0) return true;
    if (d1 == 0 && on_segment(p, a, b)) return true;
    if (d2 == 0 && on_segment(q, a, b)) return true;
    if (d3 == 0 && on_segment(a, p, q)) return true;
    if (d4 == 0 && on_segment(b, p, q)) return true;
    return false;
}

bool Walkable::inside(Point p) const {
    return std::any_of(plan.rooms.begin(), plan.rooms.end(), [&](const Room& r) { return r.contains(p); });
}

bool Walkable::can_move(Point from, Point to) const {
    if (!inside(to)) return false;
    if (!walls_between_rooms || !inside(from)) return true;
    for (const Room& room : plan.rooms)
        if (room.contains(from) && room.contains(to) && segment_within(room, from, to)) return true;
    return std::any_of(doors.begin(), doors.end(),
                       [&](const Segment& d) { return segments_intersect(from, to, d.a, d.b); });
}

}  // namespace locus::fusion
