#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "locus/plan/instructions.hpp"

namespace plan_instructions_test {
namespace {

using locus::Point;
using namespace locus::plan;

Leg leg(std::vector<Point> path) { return Leg{1, 0, std::move(path), 0.0}; }

std::vector<std::string> texts(const std::vector<Step>& steps) {
    std::vector<std::string> out;
    for (const Step& s : steps) out.push_back(s.text);
    return out;
}

TEST(PlanInstructions, LShapedLegIsWalkTurnLeftWalkArrive) {
    const auto steps = instructions({leg({{0, 0}, {10, 0}, {10, 12}})}, {});
    EXPECT_EQ(texts(steps), (std::vector<std::string>{"Walk 10 m", "Turn left", "Walk 12 m", "Arrive at your destination"}));
    ASSERT_EQ(steps.size(), 4u);
    EXPECT_EQ(steps[0].kind, StepKind::walk);
    EXPECT_DOUBLE_EQ(steps[0].distance_m, 10.0);
    EXPECT_EQ(steps[1].kind, StepKind::turn_left);
    EXPECT_EQ(steps[3].kind, StepKind::arrive);
}

TEST(PlanInstructions, TurnsAreGradedByAngle) {
    // 10 m legs heading east, then turning 30° right, 100° right, 150° left and 10° left.
    std::vector<Point> path{{0, 0}, {10, 0}};
    double heading = 0.0;
    for (const double turn : {-30.0, -100.0, 150.0, 10.0}) {
        heading += turn * std::numbers::pi / 180.0;
        path.push_back({path.back().x + 10 * std::cos(heading), path.back().y + 10 * std::sin(heading)});
    }
    const auto steps = instructions({leg(path)}, {});
    std::vector<StepKind> turns;
    for (const Step& s : steps)
        if (s.kind != StepKind::walk && s.kind != StepKind::arrive) turns.push_back(s.kind);
    EXPECT_EQ(turns, (std::vector<StepKind>{StepKind::slight_right, StepKind::turn_right, StepKind::sharp_left}));
}

TEST(PlanInstructions, JogThroughADoorIsNoTurn) {
    // 45° left and 45° right within 0.7 m: one straight walk.
    const auto steps = instructions({leg({{0, 0}, {10, 0}, {10.5, 0.5}, {20, 0.5}})}, {});
    EXPECT_EQ(texts(steps), (std::vector<std::string>{"Walk 20 m", "Arrive at your destination"}));
}

TEST(PlanInstructions, BendsCloseTogetherAddUpToOneTurn) {
    // Two 45° left bends 0.7 m apart make one left turn.
    const auto steps = instructions({leg({{0, 0}, {10, 0}, {10.5, 0.5}, {10.5, 10}})}, {});
    EXPECT_EQ(texts(steps), (std::vector<std::string>{"Walk 11 m", "Turn left", "Walk 10 m", "Arrive at your destination"}));
}

TEST(PlanInstructions, ConnectorsSayKindDirectionAndLevel) {
    const std::vector<Leg> legs = {leg({{0, 0}, {5, 0}}), leg({{5, 0}, {5, 3}}), leg({{5, 3}, {1, 3}})};
    const std::vector<Transfer> transfers = {{ConnectorKind::stairs, "Main stairs", 0, 2, 12.0}, {ConnectorKind::elevator, "Lift", 2, 1, 30.0}};
    const auto steps = instructions(legs, transfers);
    EXPECT_EQ(texts(steps), (std::vector<std::string>{"Walk 5 m", "Take the stairs up to level 2", "Walk 3 m",
                                                      "Take the elevator down to level 1", "Walk 4 m", "Arrive at your destination"}));
    EXPECT_EQ(steps[1].kind, StepKind::take_connector);
    EXPECT_EQ(steps[1].connector, ConnectorKind::stairs);
    EXPECT_EQ(steps[1].connector_name, "Main stairs");
    EXPECT_EQ(steps[1].from_level, 0);
    EXPECT_EQ(steps[1].to_level, 2);
}

TEST(PlanInstructions, ShortWalkIsAtLeastOneMetre) {
    EXPECT_EQ(instructions({leg({{0, 0}, {0.3, 0}})}, {})[0].text, "Walk 1 m");
}

}  // namespace
}  // namespace plan_instructions_test
