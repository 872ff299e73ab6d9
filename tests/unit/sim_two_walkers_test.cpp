// Bonjorn López 2016's two walkers: with exact ranging and A heading at B, the estimator points at B;
// with A walking 90° off B it can only ever report the walked direction (|w| = cos α < 0.5 is
// discarded), which is the thesis's own finding for walks not aimed at the other person.
#include <gtest/gtest.h>

#include "sim/two_walkers.hpp"

namespace sim_two_walkers_test {
namespace {

using namespace locus::sim;

TEST(TwoWalkers, ExactRangingWalkingAtBPointsAtB) {
    TwoWalkerConfig c;
    c.initial_spread_deg = 0.0;
    const auto s = evaluate_two_walkers(c, RelativeMethod::Exact, 1, 20);
    EXPECT_LT(s.median_error_deg, 20.0);
    EXPECT_GT(s.met_share, 0.7);
    EXPECT_DOUBLE_EQ(s.median_distance_error, 0.0);
}

TEST(TwoWalkers, WalkingSidewaysGivesNoEstimate) {
    TwoWalkerConfig c;
    c.initial_spread_deg = 0.0;
    c.heading_sigma_deg = 0.0;
    c.heading_bias_deg = 90.0;  // the walker believes it heads at B but walks at right angles
    // 10 s: at most 14 m sideways, where w = (20 − √(400 + 14²)) / 14 ≈ −0.31 is still
    // discarded (far beyond, walking away, it would tend to −1 and count).
    c.seconds = 10.0;
    const auto r = run_two_walkers(c, RelativeMethod::Exact, 3);
    EXPECT_FALSE(r.met);
    EXPECT_EQ(r.steps_without_estimate, r.steps);
}

TEST(TwoWalkers, SameSeedSameWalk) {
    TwoWalkerConfig c;
    const auto a = run_two_walkers(c, RelativeMethod::Rssi, 7);
    const auto b = run_two_walkers(c, RelativeMethod::Rssi, 7);
    EXPECT_EQ(a.errors_deg, b.errors_deg);
    EXPECT_GT(a.distance_errors.front() + a.distance_errors.back(), 0.0);
}

// With both phones' fused fixes the bearing needs no walk at all, wherever A first heads.
TEST(TwoWalkers, BothFixesPointAtBFromAnyStart) {
    TwoWalkerConfig c;
    c.initial_spread_deg = 180.0;
    const auto s = evaluate_two_walkers(c, RelativeMethod::BothFixes, 1, 20);
    EXPECT_LT(s.median_error_deg, 20.0);
    EXPECT_GT(s.met_share, 0.9);
    c.fix_sigma = 0.0;  // exact fixes: only the compass bias and heading noise remain in the walk
    EXPECT_LT(evaluate_two_walkers(c, RelativeMethod::BothFixes, 1, 5).median_error_deg, 1e-9);
}

// Smoothed RSSI and a longer baseline before a weight (min_rho): walking at B, the estimate
// points at B; with the thesis's 0.5 m it is mostly noise.
TEST(TwoWalkers, SmoothedRssiWithALongBaselinePointsAtB) {
    TwoWalkerConfig c;
    c.initial_spread_deg = 0.0;
    c.estimator.min_rho = 6.0;
    const auto tuned = evaluate_two_walkers(c, RelativeMethod::RssiKalman, 1, 40);
    EXPECT_LT(tuned.median_error_deg, 20.0);
    c.estimator.min_rho = 0.5;
    EXPECT_GT(evaluate_two_walkers(c, RelativeMethod::RssiKalman, 1, 40).median_error_deg, 2 * tuned.median_error_deg);
}

}  // namespace
}  // namespace sim_two_walkers_test
