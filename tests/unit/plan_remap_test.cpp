// A plan made on one floor, fitted to another (tools/plan_remap.hpp).
#include "plan_remap.hpp"

#include <gtest/gtest.h>

namespace plan_remap_test {
namespace {

using locus::plan::Connector;
using locus::plan::ConnectorLink;
using locus::plan::Plan;
using locus::plan::Space;
using locus::tools::FloorIds;
using locus::tools::remap_plan;

TEST(PlanRemap, LinksTheTargetFloorDoesNotKnowAreDropped) {
    Plan plan;
    Space lobby, cafe, unnamed;
    lobby.name = "Lobby";
    lobby.room_id = 1;  // a room of the floor it was exported from
    cafe.name = "Cafe";
    cafe.room_id = 7;  // one of the target's own
    plan.spaces = {lobby, cafe, unnamed};
    Connector stairs;
    stairs.id = "S1";
    stairs.poi_id = 3;
    stairs.links = {ConnectorLink{2, "S1"}, ConnectorLink{5, "S1"}, ConnectorLink{9, "S9"}};
    plan.connectors = {stairs};

    const FloorIds target{.floor_id = 5, .rooms = {7, 8}, .pois = {4}, .map_floors = {2, 5, 6}};
    const auto report = remap_plan(plan, target);
    EXPECT_FALSE(plan.spaces[0].room_id.has_value());
    EXPECT_EQ(plan.spaces[1].room_id, 7);
    EXPECT_FALSE(plan.spaces[2].room_id.has_value());
    EXPECT_EQ(plan.spaces[0].name, "Lobby");  // kept: the server matches the room by name
    EXPECT_FALSE(plan.connectors[0].poi_id.has_value());
    ASSERT_EQ(plan.connectors[0].links.size(), 1u);
    EXPECT_EQ(plan.connectors[0].links[0].floor_id, 2);
    EXPECT_EQ(report.room_links_kept, 1);
    EXPECT_EQ(report.room_links_dropped, 1);
    EXPECT_EQ(report.poi_links_dropped, 1);
    ASSERT_EQ(report.floor_links_dropped.size(), 2u);  // to itself, and to a floor of no map of its
    EXPECT_EQ(report.floor_links_dropped[0], "connector 'S1' → floor 5");
    EXPECT_EQ(report.floor_links_dropped[1], "connector 'S1' → floor 9");
    EXPECT_TRUE(report.changed());
}

TEST(PlanRemap, APlanOfTheSameFloorIsUnchanged) {
    Plan plan;
    Space s;
    s.name = "Hall";
    s.room_id = 4;
    plan.spaces = {s};
    const auto report = remap_plan(plan, FloorIds{.floor_id = 1, .rooms = {4}, .pois = {}, .map_floors = {1}});
    EXPECT_EQ(plan.spaces[0].room_id, 4);
    EXPECT_FALSE(report.changed());
}

}  // namespace
}  // namespace plan_remap_test
