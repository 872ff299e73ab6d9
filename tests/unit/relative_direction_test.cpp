// Bonjorn López 2016's relative-direction estimator on hand-computed cases: weight stages, the angle
// Kalman filter's wrap, the reference resets, the circle–line intersection.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "locus/motion/relative/angle_kalman.hpp"
#include "locus/motion/relative/direction_estimator.hpp"
#include "locus/motion/relative/phone_rssi.hpp"

namespace relative_direction_test {
namespace {

using namespace locus;
using namespace locus::relative;

TEST(RelativeWeights, SeedStagesCountOneToFiveTimes) {
    EXPECT_EQ(weight_repeats(0.49), 0);
    EXPECT_EQ(weight_repeats(0.5), 1);
    EXPECT_EQ(weight_repeats(0.79), 1);
    EXPECT_EQ(weight_repeats(0.8), 2);
    EXPECT_EQ(weight_repeats(1.49), 2);
    EXPECT_EQ(weight_repeats(1.5), 3);
    EXPECT_EQ(weight_repeats(3.99), 3);
    EXPECT_EQ(weight_repeats(4.0), 4);
    EXPECT_EQ(weight_repeats(8.99), 4);
    EXPECT_EQ(weight_repeats(9.0), 5);
    EXPECT_EQ(weight_repeats(15.0), 5);
    EXPECT_EQ(weight_repeats(15.01), 0);
}

TEST(AngleKalman, FirstMeasurementAsIsThenAveragesAcrossTheWrap) {
    AngleKalman k;
    EXPECT_DOUBLE_EQ(k.update(170.0), 170.0);
    // P is still 1 at the second measurement, so the gain is ~1: the estimate jumps to it,
    // through 180° rather than back across 0°.
    const double second = k.update(-170.0);
    EXPECT_NEAR(std::abs(second), 170.0, 0.1);
    // Alternating 179° / −179° settles at 180°, never near 0°.
    for (int i = 0; i < 50; ++i) k.update(i % 2 ? 179.0 : -179.0);
    EXPECT_GT(std::abs(*k.estimate()), 175.0);
}

TEST(AngleKalman, GainShrinksSoLaterOutliersMoveItLittle) {
    AngleKalman k;
    for (int i = 0; i < 30; ++i) k.update(40.0);
    // With the thesis's Q = 1e-5, R = 1e-3 the gain settles near √(Q/R) ≈ 0.1 (P ≈ √(QR)), so a
    // 60° outlier moves the estimate by about 6°, not 60°.
    const double after = k.update(100.0);
    EXPECT_GT(after, 43.0);
    EXPECT_LT(after, 48.0);
    k.reset();
    EXPECT_FALSE(k.estimate());
}

TEST(RelativeDirection, WalkingAtTheTargetPointsAtIt) {
    // B 10 m east; A walks east with exact distances: w = 1 every step.
    DirectionEstimator e;
    EXPECT_EQ(e.step({0, 0}, 10.0), StepOutcome::Reference);
    EXPECT_EQ(e.step({0.2, 0}, 9.8), StepOutcome::TooClose);
    EXPECT_EQ(e.step({1, 0}, 9.0), StepOutcome::Measured);
    EXPECT_NEAR(e.last_weight(), 1.0, 1e-12);
    EXPECT_EQ(e.step({2, 0}, 8.0), StepOutcome::Measured);
    ASSERT_TRUE(e.direction_deg());
    EXPECT_NEAR(*e.direction_deg(), 0.0, 1e-9);
    const auto b = e.target();
    ASSERT_TRUE(b);
    EXPECT_NEAR(b->x, 10.0, 1e-9);
    EXPECT_NEAR(b->y, 0.0, 1e-9);
}

TEST(RelativeDirection, WalkingAwayCountsTheOppositeDirection) {
    // B 10 m north; A walks south: w = −1, so the direction is south + 180° = north (90°).
    DirectionEstimator e;
    e.step({0, 0}, 10.0);
    EXPECT_EQ(e.step({0, -1}, 11.0), StepOutcome::Measured);
    EXPECT_NEAR(e.last_weight(), -1.0, 1e-12);
    EXPECT_NEAR(*e.direction_deg(), 90.0, 1e-9);
}

TEST(RelativeDirection, SidewaysStepsAreDiscarded) {
    // B 10 m east; A walks north: d grows by only 0.05 m over 1 m, |w| < 0.5.
    DirectionEstimator e;
    e.step({0, 0}, 10.0);
    EXPECT_EQ(e.step({0, 1}, std::hypot(10.0, 1.0)), StepOutcome::Discarded);
    EXPECT_FALSE(e.direction_deg());
    EXPECT_FALSE(e.target());
}

TEST(RelativeDirection, NlosToLosMovesTheReference) {
    // The reference distance was read through a wall (40 m for a true 10 m): the next reading
    // 1 m on gives w = 31 > 15, so the reference moves to A and the filter restarts.
    DirectionEstimator e;
    e.step({0, 0}, 40.0);
    EXPECT_EQ(e.step({1, 0}, 9.0), StepOutcome::ResetLos);
    EXPECT_DOUBLE_EQ(e.reference().x, 1.0);
    EXPECT_DOUBLE_EQ(e.reference_distance(), 9.0);
    // LOS to NLOS (w < −15) is only discarded.
    EXPECT_EQ(e.step({2, 0}, 30.0), StepOutcome::Discarded);
    EXPECT_DOUBLE_EQ(e.reference().x, 1.0);
}

TEST(RelativeDirection, ReferenceMovesWhenTheDistanceIsAFifth) {
    DirectionEstimator e;
    e.step({0, 0}, 10.0);
    for (double x = 1; x < 8; ++x) EXPECT_EQ(e.step({x, 0}, 10.0 - x), StepOutcome::Measured);
    EXPECT_EQ(e.step({8, 0}, 2.0), StepOutcome::ResetShrunk);
    EXPECT_DOUBLE_EQ(e.reference().x, 8.0);
    // The direction found before the restart is kept until the new filter has one.
    ASSERT_TRUE(e.direction_deg());
    EXPECT_NEAR(*e.direction_deg(), 0.0, 1e-9);
}

TEST(RelativeDirection, CircleLineIntersectionTakesTheFartherPoint) {
    // Ray east from the origin, circle of radius 5 around (3, 4): meets at x = 0 and x = 6.
    const auto p = ray_circle_far({0, 0}, 0.0, {3, 4}, 5.0);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->x, 6.0, 1e-9);
    EXPECT_NEAR(p->y, 0.0, 1e-9);
    EXPECT_FALSE(ray_circle_far({0, 0}, 0.0, {3, 4}, 3.0));   // circle misses the line
    EXPECT_FALSE(ray_circle_far({0, 0}, 180.0, {6, 0}, 1.0)); // only behind the origin
}

TEST(RelativeDirection, TargetUsesTheCurrentDistanceNotTheReferenceOne) {
    // Reference distance overestimated (14 m for a true 10 m); the estimate follows the
    // current, shorter and better reading: B is 6 m past A at (4, 0).
    DirectionEstimator e;
    e.step({0, 0}, 14.0);
    e.step({4, 0}, 6.0);
    const auto b = e.target();
    ASSERT_TRUE(b);
    EXPECT_NEAR(b->x, 10.0, 1e-9);
}

TEST(PhoneRssi, LogDistanceRoundTripAndMeanInDb) {
    PhoneLink link;  // −45 dBm at 1 m, n = 2.5
    EXPECT_NEAR(phone_distance(link, -45.0), 1.0, 1e-9);
    EXPECT_NEAR(phone_distance(link, -70.0), 10.0, 1e-9);
    const std::vector<double> readings{-65.0, -75.0};
    EXPECT_NEAR(phone_distance(link, readings), 10.0, 1e-9);
    EXPECT_THROW(phone_distance(link, std::span<const double>{}), std::invalid_argument);
}

}  // namespace
}  // namespace relative_direction_test
