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
#include <optional>
#include <vector>

#include "locus/geometry.hpp"
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

    bool in_spaces(Point p) const;  // in some space's polygon (holes excluded)
    bool inside(Point p) const;     // in the spaces and more than kWallMargin off every barrier
    // A move is legal when it ends inside and crosses no wall (a door gap is no wall). A point
    // off the plan altogether may only move back onto it, anywhere.
    bool can_move(Point from, Point to) const;
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
    double clearance_at(Point p) const;
    static constexpr double kClearCap = 3.0;  // metres: longer than any step

    locus::plan::Plan plan_;
    locus::plan::WalkGrid grid_;
    std::vector<float> clear_;  // per cell: clearance_at's bound, capped at kClearCap
    std::vector<locus::plan::Bounds> space_bounds_;
};

}  // namespace locus::fusion
