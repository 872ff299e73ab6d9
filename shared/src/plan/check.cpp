#include "locus/plan/check.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "locus/plan/ring.hpp"

namespace locus::plan {

namespace {

bool same(Point a, Point b) { return a.x == b.x && a.y == b.y; }

bool coordinate_ok(Point p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::abs(p.x) <= kMaxPlanCoordinate &&
           std::abs(p.y) <= kMaxPlanCoordinate;
}

std::string quoted(const std::string& what, std::size_t i, const std::string& name) {
    std::string s = what + "[" + std::to_string(i) + "]";
    if (!name.empty()) s += " '" + name + "'";
    return s;
}

// Reports the first bad coordinate only: one NaN tends to come with many.
bool check_points(const std::vector<Point>& points, const std::string& feature, std::vector<PlanProblem>& out) {
    for (std::size_t i = 0; i < points.size(); ++i)
        if (!coordinate_ok(points[i])) {
            out.push_back({feature, "point " + std::to_string(i) + " is not finite or beyond ±" +
                                        std::to_string(static_cast<long long>(kMaxPlanCoordinate)) + " m"});
            return false;
        }
    return true;
}

double cross(Point o, Point a, Point b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// Edges i and j of a closed ring (edge k runs from ring[k] to ring[k+1]).
bool ring_self_intersects(const Ring& r) {
    const std::size_t edges = r.size() - 1;
    for (std::size_t i = 0; i < edges; ++i) {
        // Neighbouring edges share a vertex; they only go wrong by folding back on each other.
        const std::size_t next = (i + 1) % edges;
        const Point a = r[i], b = r[i + 1], c = r[next + 1];
        if (cross(a, b, c) == 0.0 && (c.x - b.x) * (a.x - b.x) + (c.y - b.y) * (a.y - b.y) > 0.0) return true;
        for (std::size_t j = i + 2; j < edges; ++j) {
            if (i == 0 && j == edges - 1) continue;
            if (segments_intersect(r[i], r[i + 1], r[j], r[j + 1])) return true;
        }
    }
    return false;
}

// Returns whether the ring is usable for further checks (hole containment).
bool check_ring(const Ring& r, const std::string& feature, std::vector<PlanProblem>& out) {
    if (!check_points(r, feature, out)) return false;
    if (r.size() < 4) {
        out.push_back({feature, "ring has " + std::to_string(r.size()) + " points; a closed ring needs at least 4"});
        return false;
    }
    if (!same(r.front(), r.back())) {
        out.push_back({feature, "ring is not closed: its last point differs from its first"});
        return false;
    }
    if (signed_area(r) == 0.0) {
        out.push_back({feature, "ring has zero area"});
        return false;
    }
    if (ring_self_intersects(r)) {
        out.push_back({feature, "ring intersects itself"});
        return false;
    }
    return true;
}

void check_space(const Space& s, std::size_t index, std::vector<PlanProblem>& out) {
    const std::string feature = quoted("spaces", index, s.name);
    const bool outer_ok = check_ring(s.shape.outer, feature + " outer ring", out);
    for (std::size_t h = 0; h < s.shape.holes.size(); ++h) {
        const Ring& hole = s.shape.holes[h];
        const std::string hf = feature + " holes[" + std::to_string(h) + "]";
        if (!check_ring(hole, hf, out) || !outer_ok) continue;
        const bool vertices_inside = std::all_of(hole.begin(), hole.end(), [&](Point p) { return ring_contains(s.shape.outer, p); });
        bool edges_cross = false;
        for (std::size_t i = 0; i + 1 < hole.size() && !edges_cross; ++i)
            for (std::size_t j = 0; j + 1 < s.shape.outer.size() && !edges_cross; ++j)
                edges_cross = segments_intersect(hole[i], hole[i + 1], s.shape.outer[j], s.shape.outer[j + 1]);
        if (!vertices_inside || edges_cross) out.push_back({hf, "hole is not inside the outer ring"});
    }
}

double distance_to_walls(Point p, const std::vector<Wall>& walls) {
    double best = INFINITY;
    for (const Wall& w : walls)
        for (std::size_t i = 0; i + 1 < w.line.size(); ++i) best = std::min(best, distance_to_segment(p, w.line[i], w.line[i + 1]));
    return best;
}

}  // namespace

std::vector<PlanProblem> check_plan(const Plan& plan) {
    std::vector<PlanProblem> out;
    for (std::size_t i = 0; i < plan.spaces.size(); ++i) check_space(plan.spaces[i], i, out);

    for (std::size_t i = 0; i < plan.walls.size(); ++i) {
        const std::string feature = quoted("walls", i, "");
        const auto& line = plan.walls[i].line;
        if (!check_points(line, feature, out)) continue;
        const bool distinct = std::any_of(line.begin(), line.end(), [&](Point p) { return !same(p, line.front()); });
        if (!distinct) out.push_back({feature, "a wall needs at least 2 distinct points"});
    }

    for (std::size_t i = 0; i < plan.doors.size(); ++i) {
        const Door& d = plan.doors[i];
        const std::string feature = quoted("doors", i, d.name);
        if (!check_points({d.a, d.b}, feature, out)) continue;
        const Point mid{(d.a.x + d.b.x) / 2.0, (d.a.y + d.b.y) / 2.0};
        if (distance_to_walls(mid, plan.walls) > kDoorWallTolerance)
            out.push_back({feature, "door is not on any wall (none within 0.5 m)"});
    }

    std::set<std::string> ids;
    for (std::size_t i = 0; i < plan.connectors.size(); ++i) {
        const Connector& c = plan.connectors[i];
        const std::string feature = quoted("connectors", i, c.id);
        check_points({c.at}, feature, out);
        if (c.id.empty()) out.push_back({feature, "connector id is empty"});
        else if (!ids.insert(c.id).second) out.push_back({feature, "connector id '" + c.id + "' is used twice"});
        if (c.seconds_per_level && !(std::isfinite(*c.seconds_per_level) && *c.seconds_per_level > 0.0))
            out.push_back({feature, "seconds_per_level must be a positive number"});
        for (const ConnectorLink& link : c.links)
            if (link.connector.empty()) out.push_back({feature, "a link names no connector"});
    }

    Rect box{INFINITY, INFINITY, -INFINITY, -INFINITY};
    const auto grow = [&](Point p) {
        // Points already reported as not finite or out of range do not count twice.
        if (!(std::abs(p.x) <= kMaxPlanCoordinate && std::abs(p.y) <= kMaxPlanCoordinate)) return;
        box = {std::min(box.xmin, p.x), std::min(box.ymin, p.y), std::max(box.xmax, p.x), std::max(box.ymax, p.y)};
    };
    for (const auto& s : plan.spaces) std::for_each(s.shape.outer.begin(), s.shape.outer.end(), grow);
    for (const auto& w : plan.walls) std::for_each(w.line.begin(), w.line.end(), grow);
    for (const auto& d : plan.doors) grow(d.a), grow(d.b);
    for (const auto& c : plan.connectors) grow(c.at);
    if (box.xmin <= box.xmax && (box.xmax - box.xmin) * (box.ymax - box.ymin) > kMaxPlanArea)
        out.push_back({"the plan", "it covers " + std::to_string(static_cast<long long>(box.xmax - box.xmin)) + " m × " +
                                       std::to_string(static_cast<long long>(box.ymax - box.ymin)) +
                                       " m, more than 250,000 m² (coordinates are metres)"});
    return out;
}

}  // namespace locus::plan
