#include "locus/fusion/plan_walkable.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace locus::fusion {

namespace {

Point lerp(Point a, Point b, double t) { return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}; }

// Bisection steps of reach(): 2⁻¹² of a step (under a millimetre for a 2 m step).
constexpr int kReachIterations = 12;
// How much longer than the step itself a walk round a wall may be: the Kalman state is
// metres off, so the door the person took may be a little farther than the step.
constexpr double kDetour = 1.0;
// Sampling of snap()'s walk towards a point.
constexpr double kTowardStep = 0.05;

}  // namespace

PlanWalkable::PlanWalkable(locus::plan::Plan plan) : plan_(std::move(plan)) {
    if (plan_.spaces.empty()) throw std::invalid_argument("the floor plan has no spaces: nothing on it is walkable");
    // Clearance only decides which cells snap() may land on; crossing tests are exact.
    locus::plan::GridOptions options;
    options.clearance = kWallMargin;
    grid_ = locus::plan::build_walk_grid(plan_, options);
    for (const auto& s : plan_.spaces) space_bounds_.push_back(locus::plan::bounds_of(s.shape.outer));
    // Distance from each cell to the nearest barrier, up to kClearCap: where it exceeds a
    // move's length the move cannot cross one, and most moves are made away from walls.
    // Every bound is less half a diagonal (and a µm for float rounding), so it holds for
    // every point of the cell, not only its centre. A cell not visited below has its centre
    // more than kClearCap from every barrier.
    const double half_diagonal = grid_.options.cell * std::sqrt(0.5) + 1e-6;
    clear_.assign(static_cast<std::size_t>(grid_.cell_count()), static_cast<float>(kClearCap - half_diagonal));
    const auto clamp_col = [&](double x) { return std::clamp(static_cast<int>(std::floor((x - grid_.origin.x) / grid_.options.cell)), 0, grid_.cols - 1); };
    const auto clamp_row = [&](double y) { return std::clamp(static_cast<int>(std::floor((y - grid_.origin.y) / grid_.options.cell)), 0, grid_.rows - 1); };
    for (std::size_t i = 0; i < grid_.walls.size() + grid_.jambs.size(); ++i) {
        const Segment& s = barrier(static_cast<std::uint32_t>(i));
        for (int r = clamp_row(std::min(s.a.y, s.b.y) - kClearCap); r <= clamp_row(std::max(s.a.y, s.b.y) + kClearCap); ++r)
            for (int c = clamp_col(std::min(s.a.x, s.b.x) - kClearCap); c <= clamp_col(std::max(s.a.x, s.b.x) + kClearCap); ++c) {
                const int cell = r * grid_.cols + c;
                const double d = distance_to_segment(grid_.centre(cell), s.a, s.b) - half_diagonal;
                float& slot = clear_[static_cast<std::size_t>(cell)];
                slot = std::min(slot, static_cast<float>(std::max(0.0, d)));
            }
    }
}

const Segment& PlanWalkable::barrier(std::uint32_t i) const {
    return i < grid_.walls.size() ? grid_.walls[i] : grid_.jambs[i - grid_.walls.size()];
}

double PlanWalkable::clearance_at(Point p) const {
    const int cell = grid_.cell_at(p);
    return cell < 0 ? 0.0 : clear_[static_cast<std::size_t>(cell)];
}

bool PlanWalkable::in_spaces(Point p) const {
    // The grid knows the space at the cell's centre: nearly always the one p is in.
    if (const int cell = grid_.cell_at(p); cell >= 0) {
        const std::int32_t first = grid_.space[static_cast<std::size_t>(cell)];
        if (first >= 0 && locus::plan::polygon_contains(plan_.spaces[static_cast<std::size_t>(first)].shape, p)) return true;
    }
    for (std::size_t i = 0; i < plan_.spaces.size(); ++i)
        if (space_bounds_[i].contains(p) && locus::plan::polygon_contains(plan_.spaces[i].shape, p)) return true;
    return false;
}

bool PlanWalkable::inside(Point p) const {
    if (!in_spaces(p)) return false;
    if (clearance_at(p) > kWallMargin) return true;
    // barriers_near reaches at least bucket_m / 2 ≥ 1 m, far past the margin.
    for (std::uint32_t i : grid_.barriers_near(p, p)) {
        const Segment& s = barrier(i);
        if (distance_to_segment(p, s.a, s.b) <= kWallMargin) return false;
    }
    return true;
}

bool PlanWalkable::can_move(Point from, Point to) const {
    if (!inside(to)) return false;
    if (!in_spaces(from)) return true;
    if (clearance_at(from) > distance(from, to)) return true;
    return !grid_.crosses_barrier(from, to);
}

Point PlanWalkable::snap(Point p, std::optional<Point> toward) const {
    if (inside(p)) return p;
    if (toward) {
        // The first walkable point on the way to `toward` with no wall left between them.
        const double len = std::min(distance(p, *toward), locus::plan::kSnapRadius);
        for (double s = kTowardStep; s <= len; s += kTowardStep) {
            const Point q = lerp(p, *toward, s / distance(p, *toward));
            if (inside(q) && !grid_.crosses_barrier(q, *toward)) return q;
        }
    }
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

int PlanWalkable::nearest_reachable(Point from, Point to, double budget) const {
    int start = grid_.cell_at(from);
    if (start < 0 || !grid_.free(start)) start = grid_.snap(from, nullptr, true);
    if (start < 0) return -1;
    // Dijkstra over the grid's moves, cut at the budget: a few hundred cells for a step, so
    // the distances live in a map rather than an array the size of the floor.
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
    std::unordered_map<int, double> walked{{start, distance(from, grid_.centre(start))}};
    open.push({walked[start], start});
    int best = -1;
    double nearest = INFINITY;
    while (!open.empty()) {
        const auto [d, c] = open.top();
        open.pop();
        if (d > walked[c]) continue;
        if (const double left = distance(grid_.centre(c), to); left < nearest) {
            nearest = left;
            best = c;
        }
        const int col = c % grid_.cols, row = c / grid_.cols;
        for (int dir = 0; dir < 8; ++dir) {
            if (!(grid_.moves[static_cast<std::size_t>(c)] & (1u << dir))) continue;
            const int n = (row + locus::plan::kDirRow[dir]) * grid_.cols + col + locus::plan::kDirCol[dir];
            const double nd = d + distance(grid_.centre(c), grid_.centre(n));
            if (nd > budget) continue;
            if (auto it = walked.find(n); it != walked.end() && it->second <= nd) continue;
            walked[n] = nd;
            open.push({nd, n});
        }
    }
    return best;
}

Point PlanWalkable::step(Point from, Point to) const {
    if (can_move(from, to)) return to;
    if (!inside(from)) return snap(to);
    // Stopped at the wall and slid along it, or, when nearer to where the step aimed, the
    // nearest point a short walk away (through a door next to the wall it hit).
    const Point slid = slide(from, to);
    const int cell = nearest_reachable(from, to, distance(from, to) + kDetour);
    if (cell >= 0 && distance(grid_.centre(cell), to) < distance(slid, to)) return grid_.centre(cell);
    return slid;
}

Point PlanWalkable::slide(Point from, Point to) const {
    const double t = reach(from, to);
    const Point stop = lerp(from, to, t);
    // The wall that stopped it: the barrier nearest to the first blocked point.
    const Point blocked = lerp(from, to, std::min(1.0, t + std::pow(0.5, kReachIterations)));
    const Segment* wall = nullptr;
    double nearest = INFINITY;
    for (std::uint32_t i : grid_.barriers_near(stop, blocked)) {
        const Segment& s = barrier(i);
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
