// The walk grid's barriers listed per cell (plan/barrier_cells.hpp) and the cell-based walkable
// tests built on them (fusion::PlanWalkable): each answer must be the one testing every wall
// gives, on a plan with a thin wall between two rooms, a slanted wall, a pillar (a hole) and
// a wall reaching past the spaces, for hundreds of thousands of random points and moves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "locus/motion/fusion/plan_walkable.hpp"
#include "locus/plan/barrier_cells.hpp"
#include "locus/plan/ring.hpp"
#include "plan_fixture.hpp"

namespace plan_barrier_cells_test {
namespace {

using locus::Point;
using locus::Segment;
using namespace locus::plan;

// two_rooms (West x ∈ [0, 10], East x ∈ [10, 20], y ∈ [0, 8], door at (10, 4)) with a pillar
// in West, a slanted wall in East and a wall running out of the floor on the south side.
Plan busy_plan() {
    Plan p = plan_fixture::two_rooms();
    p.spaces[0].shape.holes.push_back(plan_fixture::rect(3, 3, 4, 4.5));
    p.walls.push_back(plan_fixture::wall({{12.3, 1.1}, {17.7, 6.4}}));
    p.walls.push_back(plan_fixture::wall({{5, 2}, {5, -3}}));
    return p;
}

std::vector<Segment> barriers_of(const WalkGrid& g) {
    std::vector<Segment> all = g.walls;
    all.insert(all.end(), g.jambs.begin(), g.jambs.end());
    return all;
}

TEST(BarrierCells, CrossingsAreThoseOfTestingEveryBarrier) {
    const WalkGrid g = build_walk_grid(busy_plan());
    const BarrierCells cells(g, 0.1);
    const auto all = barriers_of(g);
    EXPECT_EQ(cells.barrier_count(), all.size());
    EXPECT_LT(cells.entries(), static_cast<std::size_t>(g.cell_count())) << "most cells list no barrier";
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> x(-2.0, 22.0), y(-4.0, 10.0), len(0.0, 2.5), dir(-3.2, 3.2);
    int crossing = 0;
    for (int i = 0; i < 200000; ++i) {
        // Some moves start exactly on a cell corner or run along a cell edge.
        Point a{x(rng), y(rng)};
        if (i % 7 == 0) a = {std::round(a.x * 4) / 4, std::round(a.y * 4) / 4};
        const double l = len(rng), h = i % 11 == 0 ? 0.0 : dir(rng);
        const Point b{a.x + l * std::cos(h), a.y + l * std::sin(h)};
        const bool expected = std::any_of(all.begin(), all.end(), [&](const Segment& s) { return locus::segments_intersect(a, b, s.a, s.b); });
        ASSERT_EQ(cells.crosses(a, b), expected) << a.x << "," << a.y << " → " << b.x << "," << b.y;
        // The walk grid's own test agrees on moves within the grid (the only ones map
        // matching asks it about: both ends in the spaces); off it, its buckets miss walls.
        const auto on_grid = [&](Point p) { return g.cell_at(p) >= 0; };
        if (on_grid(a) && on_grid(b)) {
            EXPECT_EQ(g.crosses_barrier(a, b), expected);
        }
        crossing += expected;
        const double d = 0.1 * len(rng) / 2.5;
        const bool near = std::any_of(all.begin(), all.end(), [&](const Segment& s) { return locus::distance_to_segment(a, s.a, s.b) <= d; });
        ASSERT_EQ(cells.near(a, d), near) << a.x << "," << a.y << " within " << d;
    }
    EXPECT_GT(crossing, 10000);  // the sample does test crossings
}

TEST(BarrierCells, AMoveWithinTheMarginIsAnsweredByItsStartCell) {
    const WalkGrid g = build_walk_grid(busy_plan());
    const BarrierCells cells(g, 1.0);
    const auto all = barriers_of(g);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> x(0.0, 20.0), y(0.0, 8.0), len(0.0, 1.0), dir(-3.2, 3.2);
    int crossing = 0;
    for (int i = 0; i < 200000; ++i) {
        // Some moves start on a cell corner, or end exactly a margin away along an axis.
        Point a{x(rng), y(rng)};
        if (i % 7 == 0) a = {std::round(a.x * 4) / 4, std::round(a.y * 4) / 4};
        const double l = i % 13 == 0 ? 1.0 : len(rng), h = i % 11 == 0 ? 0.0 : dir(rng);
        const Point b{a.x + l * std::cos(h), a.y + l * std::sin(h)};
        if (g.cell_at(a) < 0) continue;  // on the grid's far edge: no start cell
        const bool expected = std::any_of(all.begin(), all.end(), [&](const Segment& s) { return locus::segments_intersect(a, b, s.a, s.b); });
        ASSERT_EQ(cells.crosses_from(g.cell_at(a), a, b), expected) << a.x << "," << a.y << " → " << b.x << "," << b.y;
        crossing += expected;
    }
    EXPECT_GT(crossing, 20000);
    // A cell lists more than its own walls: the thin wall x = 10, a metre off, for a move from (9.1, 2).
    EXPECT_TRUE(cells.crosses_from(g.cell_at({9.1, 2.0}), {9.1, 2.0}, {10.05, 2.0}));
}

TEST(BarrierCells, AShortMoveThroughAThinWallIsCaught) {
    const WalkGrid g = build_walk_grid(plan_fixture::two_rooms());
    const BarrierCells cells(g, 0.1);
    // 0.15 m either side of the wall x = 10, away from the door: both ends are fine places to
    // stand, the move between them is not.
    EXPECT_TRUE(cells.crosses({9.85, 2.0}, {10.15, 2.0}));
    EXPECT_TRUE(cells.crosses({9.999, 6.0}, {10.001, 6.001}));
    EXPECT_FALSE(cells.crosses({9.85, 4.0}, {10.15, 4.0}));  // through the door
    EXPECT_FALSE(cells.crosses({2.0, 2.0}, {2.0, 2.0}));
    EXPECT_GT(cells.memory_bytes(), cells.entries() * sizeof(std::uint32_t));
}

TEST(PlanWalkable, CellTestsAgreeWithTestingEveryPolygonAndWall) {
    const Plan plan = busy_plan();
    const locus::fusion::PlanWalkable w(plan);
    const auto all = barriers_of(w.grid());
    const auto in_spaces = [&](Point p) {
        return std::any_of(plan.spaces.begin(), plan.spaces.end(), [&](const Space& s) { return polygon_contains(s.shape, p); });
    };
    const auto inside = [&](Point p) {
        return in_spaces(p) && std::none_of(all.begin(), all.end(), [&](const Segment& s) {
                   return locus::distance_to_segment(p, s.a, s.b) <= locus::fusion::PlanWalkable::kWallMargin;
               });
    };
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> x(-1.0, 21.0), y(-1.0, 9.0), len(0.0, 1.5), dir(-3.2, 3.2);
    int legal = 0, blocked = 0;
    for (int i = 0; i < 200000; ++i) {
        const Point a{x(rng), y(rng)};
        const double l = len(rng), h = dir(rng);
        const Point b{a.x + l * std::cos(h), a.y + l * std::sin(h)};
        ASSERT_EQ(w.in_spaces(a), in_spaces(a)) << a.x << "," << a.y;
        ASSERT_EQ(w.inside(a), inside(a)) << a.x << "," << a.y;
        const bool expected = inside(b) && (!in_spaces(a) || !w.grid().crosses_barrier(a, b));
        ASSERT_EQ(w.can_move(a, b), expected) << a.x << "," << a.y << " → " << b.x << "," << b.y;
        (expected ? legal : blocked)++;
    }
    EXPECT_GT(legal, 50000);
    EXPECT_GT(blocked, 20000);
    EXPECT_FALSE(w.can_move({9.85, 2.0}, {10.15, 2.0})) << "both ends walkable, the wall between";
    EXPECT_TRUE(w.can_move({9.85, 4.0}, {10.15, 4.0}));
    EXPECT_GT(w.memory_bytes(), static_cast<std::size_t>(w.grid().cell_count()));
}

}  // namespace
}  // namespace plan_barrier_cells_test
