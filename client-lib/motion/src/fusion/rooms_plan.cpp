#include "locus/motion/fusion/rooms_plan.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace locus::fusion {

namespace {

// How far off an edge a point is taken to tell which side is in the room.
constexpr double kSide = 1e-6;

// The pieces of one rectangle edge a → b (axis-parallel) that have no other rectangle of the
// room on their outer side, merged where consecutive. `cuts` are every rectangle's
// coordinates along the edge.
void outline_of_edge(const Room& room, Point a, Point b, Point outward, const std::vector<double>& cuts,
                     std::vector<locus::plan::Wall>& out) {
    const bool horizontal = a.y == b.y;
    const double from = horizontal ? std::min(a.x, b.x) : std::min(a.y, b.y);
    const double to = horizontal ? std::max(a.x, b.x) : std::max(a.y, b.y);
    std::vector<double> stops{from, to};
    for (double c : cuts)
        if (c > from && c < to) stops.push_back(c);
    std::sort(stops.begin(), stops.end());
    stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
    const auto at = [&](double s) { return horizontal ? Point{s, a.y} : Point{a.x, s}; };
    double run = NAN;
    for (std::size_t i = 0; i + 1 <= stops.size(); ++i) {
        bool wall = false;
        if (i + 1 < stops.size()) {
            const Point m = at((stops[i] + stops[i + 1]) / 2.0);
            wall = !room.contains({m.x + kSide * outward.x, m.y + kSide * outward.y});
        }
        if (wall && std::isnan(run)) run = stops[i];
        if (!wall && !std::isnan(run)) {
            out.push_back({{at(run), at(stops[i])}});
            run = NAN;
        }
    }
}

}  // namespace

locus::plan::Plan rooms_plan(const Walkable& rooms) {
    if (rooms.floor_plan) return rooms.floor_plan->plan();
    locus::plan::Plan out;
    for (const Room& room : rooms.plan.rooms) {
        std::vector<double> xs, ys;
        for (const Rect& r : room.rects) {
            xs.insert(xs.end(), {r.xmin, r.xmax});
            ys.insert(ys.end(), {r.ymin, r.ymax});
        }
        for (const Rect& r : room.rects) {
            locus::plan::Space space;
            space.name = room.name;
            space.room_id = room.id;
            space.shape.outer = {{r.xmin, r.ymin}, {r.xmax, r.ymin}, {r.xmax, r.ymax}, {r.xmin, r.ymax}, {r.xmin, r.ymin}};
            out.spaces.push_back(std::move(space));
            if (!rooms.walls_between_rooms) continue;
            outline_of_edge(room, {r.xmin, r.ymin}, {r.xmax, r.ymin}, {0.0, -1.0}, xs, out.walls);
            outline_of_edge(room, {r.xmax, r.ymin}, {r.xmax, r.ymax}, {1.0, 0.0}, ys, out.walls);
            outline_of_edge(room, {r.xmin, r.ymax}, {r.xmax, r.ymax}, {0.0, 1.0}, xs, out.walls);
            outline_of_edge(room, {r.xmin, r.ymin}, {r.xmin, r.ymax}, {-1.0, 0.0}, ys, out.walls);
        }
    }
    if (rooms.walls_between_rooms)
        for (std::size_t i = 0; i < rooms.doors.size(); ++i)
            out.doors.push_back({rooms.doors[i].a, rooms.doors[i].b, "door " + std::to_string(i + 1)});
    return out;
}

}  // namespace locus::fusion
