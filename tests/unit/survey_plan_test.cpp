// RP grid planning (docs/spec.md §3.1: ceil(A / c²) points for area A and cell side c).
#include <gtest/gtest.h>

#include <stdexcept>

#include "survey_plan.hpp"

namespace survey_plan_test {
namespace {

using namespace locus;
using namespace locus::tools::survey_plan;

TEST(SurveyPlan, ExactGridOnAnEmptyFloor) {
    // 10 m × 6 m, 2 m cells: A/c² = 60/4 = 15 = 5 × 3 cells.
    const auto p = plan_grid(10.0, 6.0, 2.0);
    EXPECT_EQ(p.required, 15u);
    EXPECT_EQ(p.columns, 5u);
    EXPECT_EQ(p.rows, 3u);
    ASSERT_EQ(p.points.size(), 15u);
    EXPECT_EQ(p.points.front().name, "g000_000");
    EXPECT_DOUBLE_EQ(p.points.front().at.x, 1.0);
    EXPECT_DOUBLE_EQ(p.points.front().at.y, 1.0);
    EXPECT_EQ(p.points.back().name, "g002_004");
    EXPECT_DOUBLE_EQ(p.points.back().at.x, 9.0);
    EXPECT_DOUBLE_EQ(p.points.back().at.y, 5.0);
}

TEST(SurveyPlan, UnevenFloorNeverHasFewerPointsThanRequired) {
    // 30 m × 15 m, 2 m: ceil(450 / 4) = 113 required; 15 × 8 cells of 2 m × 1.875 m.
    const auto p = plan_grid(30.0, 15.0, 2.0);
    EXPECT_EQ(p.required, 113u);
    EXPECT_EQ(p.columns, 15u);
    EXPECT_EQ(p.rows, 8u);
    EXPECT_EQ(p.points.size(), 120u);
    EXPECT_DOUBLE_EQ(p.points[15].at.y, 1.875 * 1.5);  // second row centre
}

TEST(SurveyPlan, PointsOutsideEveryRoomAreDropped) {
    Room left{1, "left", {{0.0, 0.0, 6.0, 6.0}}};
    const auto p = plan_grid(10.0, 6.0, 2.0, {left});
    EXPECT_EQ(p.required, 15u);
    EXPECT_EQ(p.outside_rooms, 6u);  // columns at x = 7 and 9
    ASSERT_EQ(p.points.size(), 9u);
    for (const auto& pt : p.points) EXPECT_LT(pt.at.x, 6.0);
}

TEST(SurveyPlan, RejectsNonsense) {
    EXPECT_THROW(plan_grid(10.0, 6.0, 0.0), std::invalid_argument);
    EXPECT_THROW(plan_grid(-1.0, 6.0, 1.0), std::invalid_argument);
    EXPECT_THROW(plan_grid(1e4, 1e4, 0.001), std::invalid_argument);
}

}  // namespace
}  // namespace survey_plan_test
