#include "locus/fusion/plan_walkable.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace locus::fusion {

namespace {

Point lerp(Point a, Point b, double t) { return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}; }

// Bisection steps of reach(): 2⁻¹² of a step (under a millimetre for a 2 m step).
constexpr int kReachIterations = 12;

}  // namespace

PlanWalkable::PlanWalkable(locus::plan::Plan plan) : plan_(std::move(plan)) {
    if (plan_.spaces.empty()) throw std::invalid_argument("the floor plan has no spaces: nothing on it is walkable");
    // Clearance only decides which cells snap() may land on; crossing tests are exact.
    locus::plan::GridOptions options;
    options.clearance = kWallMargin;
    grid_ = locus::plan::build_walk_grid(plan_, options);
    for (const auto& s : plan_.spaces) space_bounds_.push_back(locus::plan::bounds_of(s.shape.outer));
}

bool PlanWalkable::in_spaces(Point p) const {
    for (std::size_t i = 0; i < plan_.spaces.size(); ++i)
        if (space_bounds_[i].contains(p) && locus::plan::polygon_contains(plan_.spaces[i].shape, p)) return true;
    return false;
}

bool PlanWalkable::inside(Point p) const {
    if (!in_spaces(p)) return false;
    // barriers_near reaches at least bucket_m / 2 ≥ 1 m, far past the margin.
    for (std::uint32_t i : grid_.barriers_near(p, p)) {
        const Segment& s = i < grid_.walls.size() ? grid_.walls[i] : grid_.jambs[i - grid_.walls.size()];
        if (distance_to_segment(p, s.a, s.b) <= kWallMargin) return false;
    }
    return true;
}

bool PlanWalkable::can_move(Point from, Point to) const {
    if (!inside(to)) return false;
    if (!in_spaces(from)) return true;
    return !grid_.crosses_barrier(from, to);
}

Point PlanWalkable::snap(Point p) const {
    if (inside(p)) return p;
    if (const int cell = grid_.snap(p, nullptr, false); cell >= 0) return grid_.centre(cell);
    // Farther than the grid's snap radius: a fix or posterior well off the plan. Rare, so
    // one pass over the grid is cheap enough.
    int best = -1;
    double nearest = INFINITY;
    for (int c = 0; c < grid_.cell_count(); ++c) {
        if (!grid_.free(c)) continue;
        const double d = distance(p, grid_.centre(c));
        if (d < nearest) {
            nearest = d;
            best = c;
        }
    }
    return best >= 0 ? grid_.centre(best) : p;
}

double PlanWalkable::reach(Point from, Point to) const {
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < kReachIterations; ++i) {
        const double mid = (lo + hi) / 2.0;
        (can_move(from, lerp(from, to, mid)) ? lo : hi) = mid;
    }
    return lo;
}

Point PlanWalkable::step(Point from, Point to) const {
    if (can_move(from, to)) return to;
    if (!inside(from)) return snap(to);
    const double t = reach(from, to);
    const Point stop = lerp(from, to, t);
    // The wall that stopped it: the barrier nearest to the first blocked point.
    const Point blocked = lerp(from, to, std::min(1.0, t + std::pow(0.5, kReachIterations)));
    const Segment* wall = nullptr;
    double nearest = INFINITY;
    for (std::uint32_t i : grid_.barriers_near(stop, blocked)) {
        const Segment& s = i < grid_.walls.size() ? grid_.walls[i] : grid_.jambs[i - grid_.walls.size()];
        const double d = distance_to_segment(blocked, s.a, s.b);
        if (d < nearest) {
            nearest = d;
            wall = &s;
        }
    }
    const double len = wall ? distance(wall->a, wall->b) : 0.0;
    if (len == 0.0) return stop;
    const Point along{(wall->b.x - wall->a.x) / len, (wall->b.y - wall->a.y) / len};
    const double rest = (to.x - stop.x) * along.x + (to.y - stop.y) * along.y;
    const Point slid{stop.x + rest * along.x, stop.y + rest * along.y};
    return lerp(stop, slid, reach(stop, slid));
}

}  // namespace locus::fusion
