#pragma once
// Hand-built plans for the plan_* tests: rectangles, walls and doors in a few lines.
#include <string>
#include <utility>
#include <vector>

#include "locus/plan/plan.hpp"

namespace plan_fixture {

using locus::Point;
using namespace locus::plan;

inline Ring rect(double x0, double y0, double x1, double y1) {
    return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}};
}

inline Space space(std::string name, Ring outer, std::vector<Ring> holes = {}) {
    Space s;
    s.name = std::move(name);
    s.shape = {std::move(outer), std::move(holes)};
    return s;
}

inline Wall wall(std::vector<Point> line) { return Wall{std::move(line)}; }

inline Door door(Point at, std::string name = "") { return Door{at, at, std::move(name)}; }
inline Door door_between(Point a, Point b, std::string name = "") { return Door{a, b, std::move(name)}; }

inline Connector connector(std::string id, ConnectorKind kind, Point at, std::vector<ConnectorLink> links) {
    Connector c;
    c.id = std::move(id);
    c.kind = kind;
    c.name = c.id;
    c.at = at;
    c.step_free = kind == ConnectorKind::elevator || kind == ConnectorKind::ramp;
    c.links = std::move(links);
    return c;
}

// Two 10 m × 8 m rooms side by side, the wall x = 10 between them with a door at (10, 4);
// the outer walls are drawn too.
inline Plan two_rooms(bool with_door = true) {
    Plan p;
    p.spaces = {space("West", rect(0, 0, 10, 8)), space("East", rect(10, 0, 20, 8))};
    p.walls = {wall({{10, 0}, {10, 8}}), wall({{0, 0}, {20, 0}, {20, 8}, {0, 8}, {0, 0}})};
    if (with_door) p.doors = {door({10, 4}, "D")};
    return p;
}

}  // namespace plan_fixture
