#include "locus/motion/fusion/plan_walkable.hpp"

#include "locus/motion/fusion/walk_filter.hpp"

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
    inv_cell_ = 1.0 / grid_.options.cell;
    for (const auto& s : plan_.spaces) space_bounds_.push_back(locus::plan::bounds_of(s.shape.outer));
    // Distance from each cell to the nearest barrier, up to kClearCap: where it exceeds a
    // move's length the move cannot cross one, and most moves are made away from walls.
    // Every bound is less half a diagonal (and a µm for float rounding), so it holds for
    // every point of the cell, not only its centre. A cell not visited below has its centre
    // more than kClearCap from every barrier.
    const double half_diagonal = grid_.options.cell * std::sqrt(0.5) + 1e-6;
    clear_.assign(static_cast<std::size_t>(grid_.cell_count()), static_cast<float>(kClearCap - half_diagonal));
    centre_clear_.assign(static_cast<std::size_t>(grid_.cell_count()), static_cast<float>(kClearCap - 1e-6));
    const auto clamp_col = [&](double x) { return std::clamp(static_cast<int>(std::floor((x - grid_.origin.x) / grid_.options.cell)), 0, grid_.cols - 1); };
    const auto clamp_row = [&](double y) { return std::clamp(static_cast<int>(std::floor((y - grid_.origin.y) / grid_.options.cell)), 0, grid_.rows - 1); };
    for (std::size_t i = 0; i < grid_.walls.size() + grid_.jambs.size(); ++i) {
        const Segment& s = barrier(static_cast<std::uint32_t>(i));
        for (int r = clamp_row(std::min(s.a.y, s.b.y) - kClearCap); r <= clamp_row(std::max(s.a.y, s.b.y) + kClearCap); ++r)
            for (int c = clamp_col(std::min(s.a.x, s.b.x) - kClearCap); c <= clamp_col(std::max(s.a.x, s.b.x) + kClearCap); ++c) {
                const int cell = r * grid_.cols + c;
                const double centre_d = distance_to_segment(grid_.centre(cell), s.a, s.b);
                const double d = centre_d - half_diagonal;
                float& at_centre = centre_clear_[static_cast<std::size_t>(cell)];
                at_centre = std::min(at_centre, static_cast<float>(std::max(0.0, centre_d - 1e-6)));
                float& slot = clear_[static_cast<std::size_t>(cell)];
                slot = std::min(slot, static_cast<float>(std::max(0.0, d)));
            }
    }
    // Which cells a space's ring passes (every cell whose centre is within half a diagonal of
    // it, and a µm more): only there does "in the spaces" change within the cell. Those cells
    // list the edges that pass them.
    const std::size_t cell_count = static_cast<std::size_t>(grid_.cell_count());
    space_kind_.assign(cell_count, kIn);
    std::vector<std::vector<RingEdge>> edges_of(cell_count);
    for (std::size_t si = 0; si < plan_.spaces.size(); ++si) {
        const auto mark = [&](const locus::plan::Ring& ring) {
            for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
                const Point a = ring[i], b = ring[i + 1];
                for (int r = clamp_row(std::min(a.y, b.y) - half_diagonal); r <= clamp_row(std::max(a.y, b.y) + half_diagonal); ++r)
                    for (int c = clamp_col(std::min(a.x, b.x) - half_diagonal); c <= clamp_col(std::max(a.x, b.x) + half_diagonal); ++c) {
                        const int cell = r * grid_.cols + c;
                        const double d = distance_to_segment(grid_.centre(cell), a, b);
                        if (d > half_diagonal) continue;
                        auto& kind = space_kind_[static_cast<std::size_t>(cell)];
                        kind = d < 1e-9 || kind == kExact ? kExact : kMixed;
                        edges_of[static_cast<std::size_t>(cell)].push_back({{a, b}, static_cast<std::uint32_t>(si), false});
                    }
            }
        };
        mark(plan_.spaces[si].shape.outer);
        for (const auto& h : plan_.spaces[si].shape.holes) mark(h);
    }
    ring_first_.assign(cell_count + 1, 0);
    for (std::size_t c = 0; c < cell_count; ++c) {
        auto& kind = space_kind_[c];
        const Point centre = grid_.centre(static_cast<int>(c));
        if (kind == kIn) {
            kind = in_spaces_exact(centre) ? kIn : kOut;
        } else if (kind == kMixed) {
            auto& edges = edges_of[c];
            std::stable_sort(edges.begin(), edges.end(), [](const RingEdge& a, const RingEdge& b) { return a.space < b.space; });
            // A space no ring of which passes the cell, holding its centre, holds all of it.
            bool held = false;
            for (std::size_t si = 0; si < plan_.spaces.size() && !held; ++si) {
                if (!space_bounds_[si].contains(centre)) continue;
                const bool passes = std::any_of(edges.begin(), edges.end(), [&](const RingEdge& e) { return e.space == si; });
                held = !passes && locus::plan::polygon_contains(plan_.spaces[si].shape, centre);
            }
            if (held) {
                kind = kIn;
            } else {
                for (auto& e : edges) e.centre_in = locus::plan::polygon_contains(plan_.spaces[e.space].shape, centre);
                ring_edges_.insert(ring_edges_.end(), edges.begin(), edges.end());
            }
        }
        ring_first_[c + 1] = static_cast<std::uint32_t>(ring_edges_.size());
    }
    cells_ = locus::plan::BarrierCells(grid_, kWallMargin);
    step_cells_ = locus::plan::BarrierCells(grid_, kStepReach);
    axis_ = corridor_axis(plan_);
}

const Segment& PlanWalkable::barrier(std::uint32_t i) const {
    return i < grid_.walls.size() ? grid_.walls[i] : grid_.jambs[i - grid_.walls.size()];
}

bool PlanWalkable::in_spaces_exact(Point p) const {
    // The grid knows the space at the cell's centre: nearly always the one p is in.
    if (const int cell = grid_.cell_at(p); cell >= 0) {
        const std::int32_t first = grid_.space[static_cast<std::size_t>(cell)];
        if (first >= 0 && locus::plan::polygon_contains(plan_.spaces[static_cast<std::size_t>(first)].shape, p)) return true;
    }
    for (std::size_t i = 0; i < plan_.spaces.size(); ++i)
        if (space_bounds_[i].contains(p) && locus::plan::polygon_contains(plan_.spaces[i].shape, p)) return true;
    return false;
}

bool PlanWalkable::in_spaces_mixed(Point p, int cell) const {
    const Point c = grid_.centre(cell);
    const auto orient = [](Point a, Point b, Point q) {
        const double v = (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
        return v > 0.0 ? 1 : v < 0.0 ? -1 : 0;
    };
    const RingEdge* e = ring_edges_.data() + ring_first_[static_cast<std::size_t>(cell)];
    const RingEdge* end = ring_edges_.data() + ring_first_[static_cast<std::size_t>(cell) + 1];
    while (e != end) {
        const std::uint32_t space = e->space;
        const bool centre_in = e->centre_in;
        bool odd = false;
        for (; e != end && e->space == space; ++e) {
            const int o1 = orient(e->edge.a, e->edge.b, c), o2 = orient(e->edge.a, e->edge.b, p);
            const int o3 = orient(c, p, e->edge.a), o4 = orient(c, p, e->edge.b);
            // p on an edge, or the segment through a vertex or along an edge: the polygon test.
            if (o2 == 0 || o3 == 0 || o4 == 0 || o1 == 0) return in_spaces_exact(p);
            if (o1 != o2 && o3 != o4) odd = !odd;
        }
        if (centre_in != odd) return true;
    }
    return false;
}

std::size_t PlanWalkable::memory_bytes() const {
    std::size_t n = sizeof(*this) + cells_.memory_bytes() - sizeof(cells_) + step_cells_.memory_bytes() - sizeof(step_cells_);
    n += (clear_.capacity() + centre_clear_.capacity()) * sizeof(float) + space_kind_.capacity() + space_bounds_.capacity() * sizeof(locus::plan::Bounds);
    n += ring_first_.capacity() * sizeof(std::uint32_t) + ring_edges_.capacity() * sizeof(RingEdge);
    n += grid_.flags.capacity() + grid_.moves.capacity() + grid_.space.capacity() * sizeof(std::int32_t);
    n += (grid_.walls.capacity() + grid_.jambs.capacity()) * sizeof(Segment) + grid_.connector_cell.capacity() * sizeof(std::int32_t);
    n += grid_.buckets.capacity() * sizeof(std::vector<std::uint32_t>);
    for (const auto& b : grid_.buckets) n += b.capacity() * sizeof(std::uint32_t);
    // The plan itself: its points dominate.
    const auto ring_bytes = [](const locus::plan::Ring& r) { return r.capacity() * sizeof(Point); };
    for (const auto& sp : plan_.spaces) {
        n += sizeof(sp) + ring_bytes(sp.shape.outer) + sp.name.capacity();
        for (const auto& h : sp.shape.holes) n += sizeof(h) + ring_bytes(h);
    }
    for (const auto& w : plan_.walls) n += sizeof(w) + w.line.capacity() * sizeof(Point);
    n += plan_.doors.capacity() * sizeof(locus::plan::Door) + plan_.connectors.capacity() * sizeof(locus::plan::Connector);
    return n;
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
