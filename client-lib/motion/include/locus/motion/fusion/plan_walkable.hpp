#pragma once
// Where a pedestrian can walk, read from a floor plan as the server holds it (plan::Plan:
// spaces, walls, door gaps): the map matching of the particle and Kalman filters when the
// floor has a plan. The geometry is the core's walk grid (locus/plan/walk_grid.hpp): its
// barriers (walls minus door gaps, plus the outline of the spaces) and its exact crossing
// test, so routing and map matching agree on what a wall is.
//
// Walkable here means "inside the spaces and more than kWallMargin from every barrier", not
// the routing grid's free cells: routing keeps 0.3 m (plus half a cell) off walls to draw
// comfortable paths, but a person may stand next to a wall, and a particle cloud cut off
// 0.5 m short of every wall would pull the estimate off a narrow corridor's edge. The margin
// stands for half a wall's thickness, which a plan's zero-width wall lines do not have.
//
// inside() and can_move() are what a particle filter asks for every particle at every step,
// so they cost the same however many walls the plan has: a cell lookup says whether the
// point's cell lies wholly inside the spaces, wholly outside or on an outline (only then a
// polygon test), and how far its nearest barrier at least is; a move whose two ends are
// together farther from every barrier than the move is long crosses none, and any other is
// tested only against the barriers listed in the cell it starts from (those within a step's
// reach of it) or, for a longer move, in the cells it passes (plan::BarrierCells). Both
// answers are exactly those of testing every wall. Built once per plan: a floor's tracks share
// one (Walkable holds it by shared_ptr); memory_bytes() says what it holds.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/plan/barrier_cells.hpp"
#include "locus/plan/plan.hpp"
#include "locus/plan/ring.hpp"
#include "locus/plan/walk_grid.hpp"

namespace locus::fusion {

class PlanWalkable {
public:
    static constexpr double kWallMargin = 0.1;  // metres, half an interior wall

    // Throws std::invalid_argument for a plan without spaces (nothing is walkable) and
    // std::length_error for one past the walk grid's size bound. Expects a plan that passes
    // plan::check_plan, as every plan the server stores does.
    explicit PlanWalkable(locus::plan::Plan plan);

    const locus::plan::Plan& plan() const { return plan_; }
    const locus::plan::WalkGrid& grid() const { return grid_; }

    // In some space's polygon (holes excluded).
    bool in_spaces(Point p) const { return in_spaces_at(p, cell_of(p)); }
    // In the spaces and more than kWallMargin off every barrier.
    bool inside(Point p) const { return inside_at(p, cell_of(p)); }
    // A move is legal when it ends inside and crosses no wall (a door gap is no wall). A point
    // off the plan altogether may only move back onto it, anywhere.
    bool can_move(Point from, Point to) const {
        const int at_to = cell_of(to);
        if (!inside_at(to, at_to)) return false;
        const int at_from = cell_of(from);
        if (!in_spaces_at(from, at_from)) return true;
        // A barrier crossed at q is no farther than |from q| from `from` and |q to| from `to`.
        const double dx = to.x - from.x, dy = to.y - from.y, d2 = dx * dx + dy * dy;
        const double c = clear_at(at_from), both = c + clear_at(at_to);
        if (c * c > d2 || both * both > d2) return true;
        // The same with each end's own bound (its cell centre's clearance less its distance
        // from the centre), tighter than the cell's by half a diagonal at most.
        if (at_from >= 0 && at_to >= 0 && point_clear(from, at_from) + point_clear(to, at_to) > std::sqrt(d2)) return true;
        // A step's move: its start cell lists every barrier it can meet. A longer one: the cells it passes.
        if (at_from >= 0 && d2 <= kStepReach * kStepReach) return !step_cells_.crosses_from(at_from, from, to);
        return !cells_.crosses(from, to);
    }
    // The plan's corridor axis (corridor_axis in walk_filter.hpp), worked out once.
    std::optional<double> axis() const { return axis_; }
    // What this object holds on the heap and in itself (the plan, the grid, the cell lists).
    std::size_t memory_bytes() const;
    // p when inside. Else, given `toward` (a Kalman posterior and its fix): the first
    // walkable point on the way from p to it that no wall parts from it, within
    // plan::kSnapRadius, so a posterior caught in a wall lands on the fix's side. Else the
    // centre of the nearest free cell of the grid (at least ~0.2 m off walls): the grid's own
    // snap within kSnapRadius, a scan of the whole grid beyond. p itself only when the grid
    // has no free cell at all.
    Point snap(Point p, std::optional<Point> toward = std::nullopt) const;
    // Where a dead-reckoned step from → to ends: `to` when the move is legal. Else, of two
    // candidates, the one nearer to `to`: stopped short of the wall it hits and slid along it
    // by the rest of the step (a corridor walked with a slightly wrong heading), or the free
    // cell nearest to `to` that a walk over the grid of the step's length plus 1 m reaches
    // from `from` (round a door jamb it clipped). Never through a wall.
    Point step(Point from, Point to) const;

private:
    // Largest t in [0, 1] such that from → from + t(to − from) is legal (bisection).
    double reach(Point from, Point to) const;
    // Stopped where from → to first becomes illegal, then slid along the nearest barrier.
    Point slide(Point from, Point to) const;
    // The free cell nearest `to` among those a walk of at most `budget` metres over the
    // grid's moves reaches from `from`; −1 when from has no free cell near it.
    int nearest_reachable(Point from, Point to, double budget) const;

    const Segment& barrier(std::uint32_t i) const;  // as WalkGrid::buckets index them
    // A lower bound of the distance from p to the nearest barrier (0 off the grid).
    double clearance_at(Point p) const { return clear_at(cell_of(p)); }
    // The grid's cell_at, with a multiplication and truncation (no floor: the range test comes
    // first): a point within rounding of a cell's edge may land in its neighbour, which the
    // cell data's µm of slack covers.
    int cell_of(Point p) const {
        const double fc = (p.x - grid_.origin.x) * inv_cell_, fr = (p.y - grid_.origin.y) * inv_cell_;
        if (!(fc >= 0.0 && fr >= 0.0 && fc < grid_.cols && fr < grid_.rows)) return -1;
        return static_cast<int>(fr) * grid_.cols + static_cast<int>(fc);
    }
    double clear_at(int cell) const { return cell < 0 ? 0.0 : clear_[static_cast<std::size_t>(cell)]; }
    bool in_spaces_at(Point p, int cell) const {
        if (cell < 0) return in_spaces_exact(p);
        const std::uint8_t kind = space_kind_[static_cast<std::size_t>(cell)];
        return kind == kMixed ? in_spaces_mixed(p, cell) : kind == kExact ? in_spaces_exact(p) : kind == kIn;
    }
    // A cell an outline passes: each space whose ring passes it holds p when it holds the
    // cell's centre and the centre-to-p segment crosses its ring an even number of times
    // (only its edges listed in the cell can be crossed); polygon tests when that is degenerate.
    bool in_spaces_mixed(Point p, int cell) const;
    bool inside_at(Point p, int cell) const {
        if (!in_spaces_at(p, cell)) return false;
        if (clear_at(cell) > kWallMargin) return true;
        // p's own bound: its cell centre's clearance less its distance from the centre.
        const double r = cell < 0 ? 0.0 : centre_clear_[static_cast<std::size_t>(cell)] - kWallMargin;
        if (r > 0.0) {
            const Point c = centre_of(p);
            if ((p.x - c.x) * (p.x - c.x) + (p.y - c.y) * (p.y - c.y) < r * r) return true;
        }
        return !cells_.near(p, kWallMargin);
    }
    // The centre of p's cell (cell_of(p) ≥ 0), without the integer division of grid_.centre.
    Point centre_of(Point p) const {
        const double fc = (p.x - grid_.origin.x) * inv_cell_, fr = (p.y - grid_.origin.y) * inv_cell_;
        return {grid_.origin.x + (static_cast<int>(fc) + 0.5) * grid_.options.cell, grid_.origin.y + (static_cast<int>(fr) + 0.5) * grid_.options.cell};
    }
    // A lower bound of p's distance to the nearest barrier, p in cell `cell` (≥ 0): the
    // centre's less |p − centre| (the triangle inequality; negative near a wall).
    double point_clear(Point p, int cell) const {
        const Point c = centre_of(p);
        return centre_clear_[static_cast<std::size_t>(cell)] - std::sqrt((p.x - c.x) * (p.x - c.x) + (p.y - c.y) * (p.y - c.y));
    }
    bool in_spaces_exact(Point p) const;  // the polygon tests
    static constexpr double kClearCap = 3.0;  // metres: longer than any step
    // Metres: nearly every move of a step (a detected step of ~0.7 m, scaled and noisy). Past
    // 1 m the lists grow faster than the moves they serve (on the PUTMC plan 0.8 m, 1.0 m and
    // 1.3 m gave a request of 1.25, 1.18 and 1.19 ms, `thin_fusion_bench`).
    static constexpr double kStepReach = 1.0;
    // Per cell: no space's ring passes it (kIn, kOut: all of it in the spaces or none), or one does.
    // kExact: a ring passes the centre itself, so only the polygon tests decide.
    enum SpaceKind : std::uint8_t { kMixed = 0, kIn = 1, kOut = 2, kExact = 3 };
    // A ring edge listed in a cell it passes, with whether its space holds that cell's centre.
    struct RingEdge {
        Segment edge;
        std::uint32_t space;
        bool centre_in;
    };

    locus::plan::Plan plan_;
    locus::plan::WalkGrid grid_;
    double inv_cell_ = 1.0;
    std::vector<float> clear_;  // per cell: clearance_at's bound, capped at kClearCap
    std::vector<float> centre_clear_;  // per cell: its centre's distance to the nearest barrier (less a µm), capped
    std::vector<std::uint8_t> space_kind_;  // per cell: SpaceKind
    std::vector<std::uint32_t> ring_first_;  // per kMixed cell, where its edges start in ring_edges_ (one more at the end)
    std::vector<RingEdge> ring_edges_;       // by cell, then by space
    locus::plan::BarrierCells cells_;       // barriers within kWallMargin of each cell
    locus::plan::BarrierCells step_cells_;  // barriers within kStepReach of each cell
    std::vector<locus::plan::Bounds> space_bounds_;
    std::optional<double> axis_;
};

}  // namespace locus::fusion
