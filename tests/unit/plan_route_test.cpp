#include <gtest/gtest.h>

#include <cmath>

#include "locus/plan/route.hpp"
#include "plan_fixture.hpp"

namespace plan_route_test {
namespace {

using namespace plan_fixture;

Building one_floor(Plan p) { return build_building({{1, 0, std::move(p)}}); }

// Points every 5 cm along a polyline.
std::vector<Point> samples(const std::vector<Point>& path) {
    std::vector<Point> out;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        const int n = std::max(1, static_cast<int>(std::ceil(locus::distance(path[i], path[i + 1]) / 0.05)));
        for (int k = 0; k <= n; ++k) {
            const double t = static_cast<double>(k) / n;
            out.push_back({path[i].x + t * (path[i + 1].x - path[i].x), path[i].y + t * (path[i + 1].y - path[i].y)});
        }
    }
    return out;
}

double distance_to_polyline(Point p, const std::vector<Point>& line) {
    double best = INFINITY;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, locus::distance_to_segment(p, line[i], line[i + 1]));
    return best;
}

// A 2 m wide L: along y ∈ [0, 2] to x = 30, then up x ∈ [28, 30] to y = 30.
Plan l_corridor() {
    Plan p;
    p.spaces = {space("L", {{0, 0}, {30, 0}, {30, 30}, {28, 30}, {28, 2}, {0, 2}, {0, 0}})};
    return p;
}

// Two floors 40 m × 10 m, stairs at the west end, an elevator at the east end.
Building stairs_and_elevator(bool with_elevator = true) {
    std::vector<FloorSpec> floors;
    for (int level = 0; level < 2; ++level) {
        Plan p;
        p.spaces = {space("Hall", rect(0, 0, 40, 10))};
        const std::int64_t other = level == 0 ? 11 : 10;
        p.connectors.push_back(connector("S", ConnectorKind::stairs, {5, 5}, {{other, "S"}}));
        if (with_elevator) p.connectors.push_back(connector("E", ConnectorKind::elevator, {35, 5}, {{other, "E"}}));
        floors.push_back({10 + level, level, std::move(p)});
    }
    return build_building(std::move(floors));
}

// West and East rooms joined directly through the Lab (x ∈ [10, 20], y ∈ [0, 10]) or the long
// way round through a corridor along the top (y ∈ [10, 12]).
Plan lab_or_corridor(bool with_corridor) {
    Plan p;
    p.spaces = {space("West", rect(0, 0, 10, 10)), space("Lab", rect(10, 0, 20, 10)), space("East", rect(20, 0, 30, 10))};
    p.walls = {wall({{10, 0}, {10, 10}}), wall({{20, 0}, {20, 10}})};
    p.doors = {door({10, 5}), door({20, 5})};
    if (with_corridor) {
        p.spaces.push_back(space("Corridor", rect(0, 10, 30, 12)));
        p.walls.push_back(wall({{0, 10}, {30, 10}}));
        p.doors.push_back(door({2, 10}));
        p.doors.push_back(door({28, 10}));
    }
    return p;
}

TEST(PlanRoute, LCorridorLengthIsTheAnalyticShortestWithin2Percent) {
    const Building b = one_floor(l_corridor());
    const Point a{1, 1}, z{29, 29}, corner{28, 2};
    const Route r = route(b, {1, a}, {1, z});
    ASSERT_EQ(r.status, RouteStatus::ok);
    ASSERT_EQ(r.legs.size(), 1u);
    // The shortest way round the inner corner, kept 0.3 m off it: passing the corner at 0.3 m
    // along its bisector is within millimetres of it (and never shorter than the bare corner).
    const Point off{corner.x + 0.3 / std::sqrt(2.0), corner.y - 0.3 / std::sqrt(2.0)};
    const double analytic = locus::distance(a, off) + locus::distance(off, z);
    EXPECT_NEAR(r.length_m, analytic, 0.02 * analytic);
    EXPECT_GE(r.length_m, locus::distance(a, corner) + locus::distance(corner, z));
    EXPECT_LE(r.legs[0].path.size(), 6u) << "string pulling leaves few vertices";
    EXPECT_NEAR(r.time_s, r.length_m / 1.3, 1e-9);
    EXPECT_DOUBLE_EQ(r.legs[0].path.front().x, a.x);
    EXPECT_DOUBLE_EQ(r.legs[0].path.back().y, z.y);
}

TEST(PlanRoute, PathGoesThroughTheDoorAndNeverCrossesTheWall) {
    const Plan plan = two_rooms();
    const Building b = one_floor(plan);
    const Route r = route(b, {1, {2, 7}}, {1, {18, 7}});  // the straight line hits the wall
    ASSERT_EQ(r.status, RouteStatus::ok);
    const auto& path = r.legs.at(0).path;
    // The wall x = 10 minus the door gap y ∈ (3.55, 4.45), and the outer walls.
    const std::vector<std::pair<Point, Point>> solid = {{{10, 0}, {10, 3.55}}, {{10, 4.45}, {10, 8}}, {{0, 0}, {20, 0}},
                                                        {{20, 0}, {20, 8}},   {{20, 8}, {0, 8}},     {{0, 8}, {0, 0}}};
    int crossings = 0;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        for (const auto& [a, b2] : solid) EXPECT_FALSE(locus::segments_intersect(path[i], path[i + 1], a, b2)) << "segment " << i;
        if ((path[i].x - 10) * (path[i + 1].x - 10) < 0) {
            ++crossings;
            const double t = (10 - path[i].x) / (path[i + 1].x - path[i].x);
            const double y = path[i].y + t * (path[i + 1].y - path[i].y);
            EXPECT_GT(y, 3.55);
            EXPECT_LT(y, 4.45);
        }
    }
    EXPECT_EQ(crossings, 1);
    EXPECT_GE(path.size(), 3u);
    const double via_door = locus::distance({2, 7}, {10, 4}) + locus::distance({10, 4}, {18, 7});
    EXPECT_NEAR(r.length_m, via_door, 0.02 * via_door);
}

TEST(PlanRoute, WallWithoutADoorLeavesNoRoute) {
    const Building b = one_floor(two_rooms(false));
    const Route r = route(b, {1, {5, 4}}, {1, {15, 4}});
    EXPECT_EQ(r.status, RouteStatus::unreachable);
    EXPECT_TRUE(r.legs.empty());
    // Within one room there is a way.
    EXPECT_EQ(route(b, {1, {2, 4}}, {1, {8, 4}}).status, RouteStatus::ok);
}

// Two 40 m × 10 m floors with stairs and an elevator: 160 × 40 cells each, six landmarks
// (two connectors, four corners), so 6,400 cells, 38,400 landmark distances and 6,400 × (22 + 24)
// bytes a floor; the cells are those the grid really has.
TEST(PlanRoute, ACostIsWorkedOutFromThePlansAsTheBuildingWillHoldIt) {
    std::vector<FloorSpec> floors;
    for (int level = 0; level < 2; ++level) {
        Plan p;
        p.spaces = {space("Hall", rect(0, 0, 40, 10))};
        p.connectors.push_back(connector("S", ConnectorKind::stairs, {5, 5}, {{level == 0 ? 11 : 10, "S"}}));
        p.connectors.push_back(connector("E", ConnectorKind::elevator, {35, 5}, {{level == 0 ? 11 : 10, "E"}}));
        floors.push_back({10 + level, level, std::move(p)});
    }
    const BuildingCost cost = building_cost(floors);
    EXPECT_DOUBLE_EQ(cost.cells, 2 * 6400.0);
    EXPECT_DOUBLE_EQ(cost.landmark_cells, 2 * 6400.0 * 6);
    EXPECT_DOUBLE_EQ(cost.bytes, 2 * 6400.0 * 46);
    const Building built = build_building(floors);
    for (const Floor& f : built.floors) {
        EXPECT_EQ(f.grid.cell_count(), 6400);
        EXPECT_EQ(f.landmarks.metres.size(), 6400u * 6);
    }
    EXPECT_DOUBLE_EQ(walk_grid_cells(floors[0].plan), 6400.0);
    EXPECT_DOUBLE_EQ(building_cost({}).bytes, 0.0);
}

TEST(PlanRoute, StairsWhenShorterElevatorWhenStepFree) {
    const Building b = stairs_and_elevator();
    const Endpoint from{10, {6, 5}}, to{11, {7, 5}};
    const Route by_stairs = route(b, from, to);
    ASSERT_EQ(by_stairs.status, RouteStatus::ok);
    ASSERT_EQ(by_stairs.transfers.size(), 1u);
    EXPECT_EQ(by_stairs.transfers[0].kind, ConnectorKind::stairs);
    EXPECT_EQ(by_stairs.legs.size(), 2u);
    EXPECT_EQ(by_stairs.legs[1].floor_id, 11);
    EXPECT_NEAR(by_stairs.time_s, by_stairs.length_m / 1.3 + 6.0, 1e-9);

    RouteOptions step_free;
    step_free.step_free = true;
    const Route by_lift = route(b, from, to, step_free);
    ASSERT_EQ(by_lift.status, RouteStatus::ok);
    ASSERT_EQ(by_lift.transfers.size(), 1u);
    EXPECT_EQ(by_lift.transfers[0].kind, ConnectorKind::elevator);
    EXPECT_GT(by_lift.length_m, 55.0);  // 29 m to the lift and 28 m back
    bool said = false;
    for (const Step& s : by_lift.steps) said = said || s.text == "Take the elevator up to level 1";
    EXPECT_TRUE(said);
}

TEST(PlanRoute, ElevatorWhenItIsFasterThanTheFarStairs) {
    const Building b = stairs_and_elevator();
    const Route r = route(b, {10, {34, 5}}, {11, {36, 5}});
    ASSERT_EQ(r.status, RouteStatus::ok);
    EXPECT_EQ(r.transfers.at(0).kind, ConnectorKind::elevator);
}

TEST(PlanRoute, StepFreeWithOnlyStairsSaysStepsAreNeeded) {
    const Building b = stairs_and_elevator(false);
    RouteOptions o;
    o.step_free = true;
    EXPECT_EQ(route(b, {10, {6, 5}}, {11, {7, 5}}, o).status, RouteStatus::needs_steps);
}

TEST(PlanRoute, StairsThroughAMiddleFloorAreOneTransfer) {
    std::vector<FloorSpec> floors;
    for (int level = 0; level < 3; ++level) {
        Plan p;
        p.spaces = {space("Hall", rect(0, 0, 20, 10))};
        std::vector<ConnectorLink> links;
        if (level > 0) links.push_back({level - 1, "S"});
        if (level < 2) links.push_back({level + 1, "S"});
        p.connectors = {connector("S", ConnectorKind::stairs, {5, 5}, links)};
        floors.push_back({level, level, std::move(p)});
    }
    const Building b = build_building(std::move(floors));
    const Route r = route(b, {0, {10, 5}}, {2, {10, 5}});
    ASSERT_EQ(r.status, RouteStatus::ok);
    ASSERT_EQ(r.transfers.size(), 1u);
    EXPECT_EQ(r.transfers[0].from_level, 0);
    EXPECT_EQ(r.transfers[0].to_level, 2);
    EXPECT_DOUBLE_EQ(r.transfers[0].seconds, 12.0);
    EXPECT_EQ(r.legs.size(), 2u);
}

TEST(PlanRoute, AvoidedSpaceIsWalkedRoundAndNamedWhenItIsTheOnlyWay) {
    const Building b = one_floor(lab_or_corridor(true));
    const Endpoint from{1, {5, 5}}, to{1, {25, 5}};
    const Route direct = route(b, from, to);
    ASSERT_EQ(direct.status, RouteStatus::ok);
    EXPECT_LT(direct.length_m, 21.0);

    RouteOptions o;
    o.avoid = {{1, 1}};  // the Lab
    const Route round = route(b, from, to, o);
    ASSERT_EQ(round.status, RouteStatus::ok);
    EXPECT_GT(round.length_m, 30.0);
    for (const Point& p : samples(round.legs.at(0).path)) EXPECT_FALSE(p.x > 10 && p.x < 20 && p.y < 10) << p.x << "," << p.y;

    const Building no_corridor = one_floor(lab_or_corridor(false));
    EXPECT_EQ(route(no_corridor, from, to, o).status, RouteStatus::needs_avoided);
    o.step_free = true;
    EXPECT_EQ(route(no_corridor, from, to, o).status, RouteStatus::needs_avoided);
}

TEST(PlanRoute, BlockedByBothConstraintsSaysSo) {
    // The only way up is stairs in the East room, and the only way there is through the Lab.
    Plan ground = lab_or_corridor(false);
    ground.connectors = {connector("S", ConnectorKind::stairs, {25, 5}, {{11, "S"}})};
    Plan upper;
    upper.spaces = {space("Hall", rect(0, 0, 30, 10))};
    upper.connectors = {connector("S", ConnectorKind::stairs, {25, 5}, {{10, "S"}})};
    const Building b = build_building({{10, 0, ground}, {11, 1, upper}});
    RouteOptions o;
    o.step_free = true;
    o.avoid = {{10, 1}};
    const Endpoint from{10, {5, 5}}, to{11, {5, 5}};
    EXPECT_EQ(route(b, from, to, o).status, RouteStatus::needs_steps_and_avoided);
    EXPECT_EQ(route(b, from, to).status, RouteStatus::ok);
    EXPECT_EQ(route(b, from, {11, {50, 50}}).status, RouteStatus::end_off_plan);
}

TEST(PlanRoute, StartingInsideAnAvoidedSpaceStillLeavesIt) {
    const Building b = one_floor(lab_or_corridor(false));
    RouteOptions o;
    o.avoid = {{1, 1}};
    EXPECT_EQ(route(b, {1, {15, 5}}, {1, {25, 5}}, o).status, RouteStatus::ok);
}

TEST(PlanRoute, PathKeepsClearanceFromWallsPillarsAndTheOutline) {
    Plan p;
    Space hall = space("Hall", rect(0, 0, 30, 12), {rect(12, 4, 14, 8)});  // a pillar
    p.spaces = {hall};
    p.walls = {wall({{20, 0}, {20, 12}}), wall({{5, 12}, {5, 3}})};
    p.doors = {door_between({20, 5}, {20, 7}, "wide")};
    const Building b = one_floor(p);
    const std::vector<std::vector<Point>> obstacles = {p.walls[0].line, p.walls[1].line, hall.shape.outer, hall.shape.holes[0]};
    for (const auto& [a, z] : std::vector<std::pair<Point, Point>>{{{1, 11}, {28, 1}}, {{1, 1}, {28, 11}}, {{8, 6}, {18, 6}}}) {
        const Route r = route(b, {1, a}, {1, z});
        ASSERT_EQ(r.status, RouteStatus::ok);
        double nearest = INFINITY;
        for (const Point& s : samples(r.legs[0].path)) {
            for (const auto& line : obstacles) {
                const double d = distance_to_polyline(s, line);
                // The 2 m door leaves wall on either side of the gap y ∈ (5, 7).
                if (&line == &obstacles[0] && std::abs(s.y - 6) < 1.0 && d > 0.0) {
                    nearest = std::min(nearest, std::min(locus::distance(s, {20, 5}), locus::distance(s, {20, 7})));
                    continue;
                }
                nearest = std::min(nearest, d);
            }
        }
        EXPECT_GE(nearest, 0.3) << "from " << a.x << "," << a.y;
    }
}

TEST(PlanRoute, NarrowDoorsStayPassableWhereverTheyFallOnTheGrid) {
    for (const double width : {0.5, 0.7, 0.9}) {
        for (const double offset : {0.0, 0.06, 0.125, 0.19}) {
            Plan p = two_rooms(false);
            const double y = 4 + offset;
            p.walls[0] = wall({{10 + offset, 0}, {10 + offset, 8}});
            p.spaces[0].shape.outer = rect(0, 0, 10 + offset, 8);
            p.spaces[1].shape.outer = rect(10 + offset, 0, 20, 8);
            p.doors = {width == 0.9 ? door({10 + offset, y}) : door_between({10 + offset, y - width / 2}, {10 + offset, y + width / 2})};
            const Route r = route(one_floor(p), {1, {5, 4}}, {1, {15, 4}});
            EXPECT_EQ(r.status, RouteStatus::ok) << "width " << width << " offset " << offset;
        }
    }
}

TEST(PlanRoute, DiagonalWallDoorIsPassable) {
    Plan p;
    p.spaces = {space("Lower", {{0, 0}, {20, 0}, {0, 20}, {0, 0}}), space("Upper", {{20, 0}, {20, 20}, {0, 20}, {20, 0}})};
    p.walls = {wall({{20, 0}, {0, 20}})};
    p.doors = {door({10, 10})};
    const Route r = route(one_floor(p), {1, {4, 4}}, {1, {16, 16}});
    ASSERT_EQ(r.status, RouteStatus::ok);
    EXPECT_NEAR(r.length_m, locus::distance({4, 4}, {16, 16}), 0.3);
}

TEST(PlanRoute, EndpointsOffThePlanSnapWithin2mAndFailBeyond) {
    const Building b = one_floor(two_rooms());
    const Route near = route(b, {1, {-1, 4}}, {1, {5, 4}});
    ASSERT_EQ(near.status, RouteStatus::ok);
    EXPECT_GT(near.start.x, 0.3);  // snapped onto a free cell inside
    EXPECT_LT(near.start.x, 1.0);
    EXPECT_EQ(route(b, {1, {-5, 4}}, {1, {5, 4}}).status, RouteStatus::start_off_plan);
    EXPECT_EQ(route(b, {1, {5, 4}}, {1, {25, 4}}).status, RouteStatus::end_off_plan);
    EXPECT_EQ(route(b, {7, {5, 4}}, {1, {5, 4}}).status, RouteStatus::unknown_floor);
}

TEST(PlanRoute, AvoidByRoomId) {
    Plan p = lab_or_corridor(true);
    p.spaces[1].room_id = 321;
    const Building b = one_floor(p);
    RouteOptions o;
    o.avoid = spaces_of_room(b, 321);
    ASSERT_EQ(o.avoid.size(), 1u);
    EXPECT_GT(route(b, {1, {5, 5}}, {1, {25, 5}}, o).length_m, 30.0);
}

}  // namespace
}  // namespace plan_route_test
