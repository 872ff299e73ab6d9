#include <gtest/gtest.h>

#include "locus/plan/walk_grid.hpp"
#include "plan_fixture.hpp"

namespace plan_walk_grid_test {
namespace {

using namespace plan_fixture;

// Every allowed move as a segment between cell centres.
std::vector<locus::Segment> moves_of(const WalkGrid& g) {
    std::vector<locus::Segment> out;
    for (int c = 0; c < g.cell_count(); ++c)
        for (int d = 0; d < 8; ++d)
            if (g.moves[static_cast<std::size_t>(c)] & (1u << d)) out.push_back({g.centre(c), g.centre(c + kDirCol[d] + kDirRow[d] * g.cols)});
    return out;
}

TEST(PlanWalkGrid, FreeCellsKeepTheThresholdAndMovesCrossTheWallOnlyAtTheDoor) {
    const WalkGrid g = build_walk_grid(two_rooms());
    EXPECT_EQ(g.cols, 80);
    EXPECT_EQ(g.rows, 32);
    const std::vector<locus::Segment> solid = {{{10, 0}, {10, 3.55}}, {{10, 4.45}, {10, 8}}};
    int free = 0;
    for (int c = 0; c < g.cell_count(); ++c) {
        if (!g.free(c)) continue;
        ++free;
        for (const auto& w : solid) EXPECT_GE(locus::distance_to_segment(g.centre(c), w.a, w.b), 0.3);
        // The outline: 0.3 m plus half a diagonal step from the outer walls.
        const Point p = g.centre(c);
        EXPECT_GE(std::min({p.x, p.y, 20 - p.x, 8 - p.y}), g.clearance_threshold());
    }
    EXPECT_GT(free, 1500);
    int through = 0;
    for (const auto& m : moves_of(g)) {
        for (const auto& w : solid) EXPECT_FALSE(locus::segments_intersect(m.a, m.b, w.a, w.b));
        if ((m.a.x - 10) * (m.b.x - 10) < 0) ++through;
    }
    EXPECT_GT(through, 0) << "the door is passable";
}

TEST(PlanWalkGrid, NoDoorNoMoveAcross) {
    const WalkGrid g = build_walk_grid(two_rooms(false));
    for (const auto& m : moves_of(g)) EXPECT_FALSE((m.a.x - 10) * (m.b.x - 10) < 0);
}

TEST(PlanWalkGrid, HolesAndOutsideAreNotFree) {
    Plan p;
    p.spaces = {space("Hall", rect(0, 0, 10, 10), {rect(4, 4, 6, 6)}), space("Annex", rect(10, 0, 12, 2))};
    const WalkGrid g = build_walk_grid(p);
    EXPECT_FALSE(g.free(g.cell_at({5, 5})));
    EXPECT_FALSE(g.free(g.cell_at({11, 8})));  // inside the bounds, in no space
    EXPECT_TRUE(g.free(g.cell_at({2, 2})));
    EXPECT_TRUE(g.free(g.cell_at({11, 1})));
    EXPECT_EQ(g.space[static_cast<std::size_t>(g.cell_at({11, 1}))], 1);
    EXPECT_EQ(g.space[static_cast<std::size_t>(g.cell_at({5, 5}))], -1);
}

TEST(PlanWalkGrid, DoorCutsWallsDrawnTwiceButNotAWallPassingNearby) {
    Plan p = two_rooms();
    // Each room also draws its own outline, doubling the wall at x = 10; and a wall y = 4.4
    // splits the east room, meeting x = 10 inside the door's gap, 0.4 m from its centre.
    p.walls.push_back(wall(rect(0, 0, 10, 8)));
    p.walls.push_back(wall(rect(10, 0, 20, 8)));
    p.walls.push_back(wall({{10, 4.4}, {20, 4.4}}));
    p.doors = {door({10, 4.0})};
    const WalkGrid g = build_walk_grid(p);
    bool through = false;
    for (const auto& m : moves_of(g)) {
        EXPECT_FALSE(locus::segments_intersect(m.a, m.b, {10.3, 4.4}, {20, 4.4})) << "the nearby wall stays whole";
        through = through || (m.a.x - 10) * (m.b.x - 10) < 0;
    }
    EXPECT_TRUE(through) << "both copies of the wall are cut";
}

TEST(PlanWalkGrid, ConnectorJoinsTheGridOnItsOwnSideOfAWall) {
    Plan p = two_rooms(false);
    p.connectors = {connector("s", ConnectorKind::stairs, {9.9, 2}, {}), connector("far", ConnectorKind::stairs, {40, 40}, {})};
    const WalkGrid g = build_walk_grid(p);
    ASSERT_GE(g.connector_cell[0], 0);
    EXPECT_LT(g.centre(g.connector_cell[0]).x, 10.0);
    EXPECT_LE(locus::distance(g.centre(g.connector_cell[0]), {9.9, 2}), kSnapRadius);
    EXPECT_EQ(g.connector_cell[1], -1);
}

TEST(PlanWalkGrid, BarrierTestsAreExact) {
    const WalkGrid g = build_walk_grid(two_rooms());
    EXPECT_TRUE(g.crosses_barrier({9, 2}, {11, 2}));
    EXPECT_FALSE(g.crosses_barrier({9, 4}, {11, 4}));
    EXPECT_TRUE(g.keeps_clearance({9, 4}, {11, 4}));
    EXPECT_FALSE(g.keeps_clearance({9, 4.3}, {11, 4.3})) << "0.2 m past the jamb's clear radius";
    EXPECT_FALSE(g.keeps_clearance({2, 7.8}, {6, 7.8})) << "0.2 m from the outline";
}

}  // namespace
}  // namespace plan_walk_grid_test
