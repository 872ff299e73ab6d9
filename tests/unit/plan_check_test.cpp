#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "locus/plan/check.hpp"
#include "plan_fixture.hpp"

namespace plan_check_test {
namespace {

using namespace plan_fixture;

// The problems about `feature`, so a test sees that the right feature was blamed.
std::vector<PlanProblem> about(const std::vector<PlanProblem>& all, const std::string& feature) {
    std::vector<PlanProblem> out;
    for (const auto& p : all)
        if (p.feature.find(feature) == 0) out.push_back(p);
    return out;
}

// check_plan finds exactly one problem: about `feature`, saying `words`.
void expect_only_problem(const Plan& p, const std::string& feature, const std::string& words) {
    const auto problems = check_plan(p);
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_EQ(problems[0].feature, feature);
    EXPECT_NE(problems[0].problem.find(words), std::string::npos) << problems[0].problem;
}

TEST(PlanCheck, WellFormedPlanHasNoProblems) {
    Plan p = two_rooms();
    p.spaces[0].shape.holes = {rect(2, 2, 3, 3)};
    p.connectors = {connector("s1", ConnectorKind::stairs, {5, 4}, {{2, "s1"}})};
    EXPECT_TRUE(check_plan(p).empty());
}

TEST(PlanCheck, OpenRingIsReported) {
    Plan p = two_rooms();
    p.spaces[1].shape.outer.back() = {10, 1};
    expect_only_problem(p, "spaces[1] 'East' outer ring", "not closed");
}

TEST(PlanCheck, TooFewPointsAndZeroAreaAreReported) {
    Plan p;
    p.spaces = {space("Short", {{0, 0}, {1, 0}, {0, 0}}), space("Flat", {{0, 0}, {1, 0}, {2, 0}, {0, 0}})};
    const auto problems = check_plan(p);
    ASSERT_EQ(problems.size(), 2u);
    EXPECT_NE(problems[0].problem.find("at least 4"), std::string::npos);
    EXPECT_EQ(problems[1].feature, "spaces[1] 'Flat' outer ring");
    EXPECT_NE(problems[1].problem.find("zero area"), std::string::npos);
}

TEST(PlanCheck, SelfIntersectingRingIsReported) {
    Plan p;
    // A lopsided bow tie (so its signed area is not zero): edges (0,0)-(4,2) and (4,0)-(0,3) cross.
    p.spaces = {space("Bow", {{0, 0}, {4, 2}, {4, 0}, {0, 3}, {0, 0}}), space("Ok", rect(5, 5, 6, 6))};
    expect_only_problem(p, "spaces[0] 'Bow' outer ring", "intersects itself");
}

TEST(PlanCheck, SpikeFoldingBackIsASelfIntersection) {
    Plan p;
    p.spaces = {space("Spike", {{0, 0}, {4, 0}, {2, 0}, {2, 2}, {0, 2}, {0, 0}})};
    expect_only_problem(p, "spaces[0] 'Spike' outer ring", "intersects itself");
}

TEST(PlanCheck, NanAndHugeCoordinatesAreReported) {
    Plan p = two_rooms();
    p.walls.push_back(wall({{1, 1}, {2, std::numeric_limits<double>::quiet_NaN()}}));
    p.doors.push_back(door({2e5, 4}, "Far"));
    const auto problems = check_plan(p);
    ASSERT_EQ(problems.size(), 2u);
    EXPECT_EQ(problems[0].feature, "walls[2]");
    EXPECT_NE(problems[0].problem.find("not finite"), std::string::npos);
    EXPECT_EQ(problems[1].feature, "doors[1] 'Far'");
}

// A plan drawn in millimetres: every coordinate is in range, but the router would need a grid
// of 21.6 billion cells.
TEST(PlanCheck, APlanLargerThanAFloorCanBeIsReported) {
    Plan p;
    Space s;
    s.name = "Hall";
    s.shape.outer = {{0, 0}, {45000, 0}, {45000, 30000}, {0, 30000}, {0, 0}};
    p.spaces.push_back(s);
    const auto problems = check_plan(p);
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_EQ(problems[0].feature, "the plan");
    EXPECT_NE(problems[0].problem.find("45000 m × 30000 m"), std::string::npos) << problems[0].problem;
    s.shape.outer = {{0, 0}, {500, 0}, {500, 500}, {0, 500}, {0, 0}};  // the largest allowed
    p.spaces = {s};
    EXPECT_TRUE(check_plan(p).empty());
}

TEST(PlanCheck, HoleOutsideItsOuterRingIsReported) {
    Plan p = two_rooms();
    p.spaces[0].shape.holes = {rect(9, 2, 11, 3)};
    expect_only_problem(p, "spaces[0] 'West' holes[0]", "not inside the outer ring");
}

TEST(PlanCheck, WallOfOneRepeatedPointIsReported) {
    Plan p = two_rooms();
    p.walls.push_back(wall({{3, 3}, {3, 3}}));
    expect_only_problem(p, "walls[2]", "2 distinct points");
}

TEST(PlanCheck, DoorOffEveryWallIsReportedButOneOnAWallIsNot) {
    Plan p = two_rooms();
    p.doors.push_back(door({10.4, 2}, "Near"));  // 0.4 m from the wall: accepted
    p.doors.push_back(door({5, 4}, "Lost"));     // mid-room
    expect_only_problem(p, "doors[2] 'Lost'", "not on any wall");
}

TEST(PlanCheck, DuplicateAndEmptyConnectorIdsAreReported) {
    Plan p = two_rooms();
    p.connectors = {connector("s1", ConnectorKind::stairs, {5, 4}, {}), connector("s1", ConnectorKind::stairs, {15, 4}, {}),
                    connector("", ConnectorKind::elevator, {15, 2}, {})};
    const auto problems = check_plan(p);
    ASSERT_EQ(problems.size(), 2u);
    EXPECT_EQ(problems[0].feature, "connectors[1] 's1'");
    EXPECT_EQ(problems[1].feature, "connectors[2]");
}

TEST(PlanCheckLinks, PairedLinksPass) {
    Plan a = two_rooms(), b = two_rooms();
    a.connectors = {connector("s", ConnectorKind::stairs, {5, 4}, {{2, "s"}})};
    b.connectors = {connector("s", ConnectorKind::stairs, {5, 4}, {{1, "s"}})};
    EXPECT_TRUE(check_links({{1, &a}, {2, &b}}).empty());
}

TEST(PlanCheckLinks, UnknownFloorUnknownConnectorUnreturnedAndSelfLinksAreReported) {
    Plan a = two_rooms(), b = two_rooms();
    a.connectors = {connector("s", ConnectorKind::stairs, {5, 4}, {{2, "s"}, {3, "s"}, {2, "nope"}, {1, "s"}})};
    b.connectors = {connector("s", ConnectorKind::stairs, {5, 4}, {})};  // does not link back
    const auto problems = check_links({{1, &a}, {2, &b}});
    ASSERT_EQ(problems.size(), 4u);
    EXPECT_EQ(problems[0].feature, "floor 1 connectors[0] 's'");
    EXPECT_NE(problems[0].problem.find("does not link back"), std::string::npos);
    EXPECT_NE(problems[1].problem.find("floor 3, which is not a floor"), std::string::npos);
    EXPECT_NE(problems[2].problem.find("connector 'nope', which that floor's plan does not have"), std::string::npos);
    EXPECT_NE(problems[3].problem.find("own floor"), std::string::npos);
}

TEST(PlanCheckLinks, FloorGivenTwiceIsReported) {
    Plan a = two_rooms();
    EXPECT_EQ(about(check_links({{1, &a}, {1, &a}}), "floor 1").size(), 1u);
}

}  // namespace
}  // namespace plan_check_test
