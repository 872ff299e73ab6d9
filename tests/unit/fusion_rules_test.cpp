// Hand-computed cases for the five rules of docs/spec.md §6. The common case: previous fused
// position (0,0), PDR at (3,0), WiFi fix at (0,4), so d_pdr = 3, d_wifi = 4, δ = 5.
#include <gtest/gtest.h>

#include <stdexcept>

#include "locus/motion/fusion/rules.hpp"

namespace fusion_rules_test {
namespace {

using locus::Point;
using namespace locus::fusion;

FusionInput base(int aps = 5) {
    FusionInput in;
    in.pdr = {3.0, 0.0};
    in.wifi = {0.0, 4.0};
    in.prev = Point{0.0, 0.0};
    in.aps = aps;
    return in;
}

void expect_point(Point got, double x, double y) {
    EXPECT_NEAR(got.x, x, 1e-12);
    EXPECT_NEAR(got.y, y, 1e-12);
}

TEST(FusionRules, NamesRoundTrip) {
    for (Rule r : all_rules()) EXPECT_EQ(parse_rule(to_string(r)), r);
    EXPECT_EQ(parse_rule("proportional3"), std::nullopt);
    EXPECT_EQ(all_rules().size(), 5u);
}

TEST(FusionRules, OnlyWifiTakesTheFix) { expect_point(fuse(Rule::only_wifi, base()), 0.0, 4.0); }

TEST(FusionRules, MidpointAverages) { expect_point(fuse(Rule::midpoint, base()), 1.5, 2.0); }

TEST(FusionRules, MidpointThresholdSwitchesAtLambda) {
    RuleParams p;
    p.lambda_m = 6.0;  // δ = 5 < 6: midpoint
    expect_point(fuse(Rule::midpoint_threshold, base(), p), 1.5, 2.0);
    p.lambda_m = 4.0;  // δ = 5 ≥ 4: the PDR is deemed broken, WiFi only
    expect_point(fuse(Rule::midpoint_threshold, base(), p), 0.0, 4.0);
    p.lambda_m = 5.0;  // δ == λ: strict inequality (docs/spec.md §6.4), WiFi only
    expect_point(fuse(Rule::midpoint_threshold, base(), p), 0.0, 4.0);
}

TEST(FusionRules, ProportionalWeighsByDistanceAndApCount) {
    // α = 4/7 · (1 − (5/10)²) = 3/7; fused = 3/7·(3,0) + 4/7·(0,4) = (9/7, 16/7).
    EXPECT_NEAR(proportional_alpha(3.0, 4.0, 5, {}), 3.0 / 7.0, 1e-12);
    expect_point(fuse(Rule::proportional, base(5)), 9.0 / 7.0, 16.0 / 7.0);
    // N = 0: α = 4/7; fused = 4/7·(3,0) + 3/7·(0,4).
    expect_point(fuse(Rule::proportional, base(0)), 12.0 / 7.0, 12.0 / 7.0);
    // γ = 1, N = 5: α = 4/7 · 1/2 = 2/7; fused = 2/7·(3,0) + 5/7·(0,4).
    RuleParams g1;
    g1.gamma = 1;
    expect_point(fuse(Rule::proportional, base(5), g1), 6.0 / 7.0, 20.0 / 7.0);
}

TEST(FusionRules, ProportionalWithNAtOrAboveNmaxIsWifi) {
    expect_point(fuse(Rule::proportional, base(10)), 0.0, 4.0);
    expect_point(fuse(Rule::proportional, base(25)), 0.0, 4.0);  // min(N, N_max) keeps α ≥ 0
    EXPECT_EQ(proportional_alpha(3.0, 4.0, 25, {}), 0.0);
}

TEST(FusionRules, Proportional2IsTheNormalisedWeight) {
    // r = (1/4) / (1/4 + 1/3) = 3/7; fused = 4/7·(3,0) + 3/7·(0,4).
    EXPECT_NEAR(proportional2_r(3.0, 4.0), 3.0 / 7.0, 1e-12);
    expect_point(fuse(Rule::proportional2, base()), 12.0 / 7.0, 12.0 / 7.0);
    // Traini 2017's un-normalised β = 1/(1/4 + 1/3) = 12/7 m would exceed 1; ours stays in [0,1].
    EXPECT_LE(proportional2_r(30.0, 0.5), 1.0);
}

TEST(FusionRules, Proportional2KeepsPdrWhenTheFixRepeats) {
    FusionInput in = base();
    in.prev_wifi = Point{0.0, 4.0};
    expect_point(fuse(Rule::proportional2, in), 3.0, 0.0);
    // The refinement is proportional2's only; the other rules still fuse.
    expect_point(fuse(Rule::midpoint, in), 1.5, 2.0);
    in.prev_wifi = Point{0.0, 4.5};  // a different fix fuses normally
    expect_point(fuse(Rule::proportional2, in), 12.0 / 7.0, 12.0 / 7.0);
}

TEST(FusionRules, FirstFixTakesWifiForEveryRule) {
    FusionInput in = base();
    in.prev.reset();
    for (Rule r : all_rules()) expect_point(fuse(r, in), 0.0, 4.0);
}

TEST(FusionRules, WifiDistanceZero) {
    // The fix repeats the previous position, PDR moved 3 m.
    FusionInput in = base();
    in.wifi = {0.0, 0.0};
    EXPECT_EQ(proportional_alpha(3.0, 0.0, 5, {}), 0.0);
    expect_point(fuse(Rule::proportional, in), 0.0, 0.0);   // α = 0: all WiFi
    EXPECT_EQ(proportional2_r(3.0, 0.0), 1.0);
    expect_point(fuse(Rule::proportional2, in), 0.0, 0.0);  // r = 1: all WiFi (limit of 1/d)
}

TEST(FusionRules, PdrDistanceZero) {
    // PDR did not move, the fix is 4 m away.
    FusionInput in = base();
    in.pdr = {0.0, 0.0};
    // α = 1 · (1 − 1/4) = 3/4: fused = 3/4·(0,0) + 1/4·(0,4).
    expect_point(fuse(Rule::proportional, in), 0.0, 1.0);
    EXPECT_EQ(proportional2_r(0.0, 4.0), 0.0);
    expect_point(fuse(Rule::proportional2, in), 0.0, 0.0);  // r = 0: all PDR
}

TEST(FusionRules, BothDistancesZero) {
    FusionInput in;
    in.pdr = in.wifi = {2.0, 2.0};
    in.prev = Point{2.0, 2.0};
    in.aps = 3;
    EXPECT_EQ(proportional_alpha(0.0, 0.0, 3, {}), 0.0);
    EXPECT_EQ(proportional2_r(0.0, 0.0), 0.0);
    for (Rule r : all_rules()) expect_point(fuse(r, in), 2.0, 2.0);
}

TEST(FusionRules, RejectsParametersOutsideTheirDomain) {
    RuleParams p;
    p.n_max = 0;
    EXPECT_THROW(fuse(Rule::proportional, base(), p), std::invalid_argument);
    p = {};
    p.gamma = 0;
    EXPECT_THROW(fuse(Rule::proportional, base(), p), std::invalid_argument);
    p = {};
    p.lambda_m = -1.0;
    EXPECT_THROW(fuse(Rule::midpoint_threshold, base(), p), std::invalid_argument);
    EXPECT_THROW(fuse(Rule::midpoint, base(-1)), std::invalid_argument);
}

TEST(FusionRules, TunedWeightsMoveTheFusedPointTowardsTheFix) {
    // The defaults are Traini 2017's rules exactly; the real-walk tuning moves the weights.
    RuleParams p;
    p.midpoint_wifi_weight = 0.75;  // 0.25·(3,0) + 0.75·(0,4)
    expect_point(fuse(Rule::midpoint, base(), p), 0.75, 3.0);
    p.lambda_m = 6.0;  // δ = 5 < 6: the weighted midpoint
    expect_point(fuse(Rule::midpoint_threshold, base(), p), 0.75, 3.0);
    // proportional2: r = 3/7 < 0.6, so the floor 0.6 is the fix's weight.
    RuleParams q;
    q.proportional2_min_r = 0.6;
    expect_point(fuse(Rule::proportional2, base(), q), 1.2, 2.4);
    q.proportional2_min_r = 0.2;  // r = 3/7 above the floor: unchanged
    expect_point(fuse(Rule::proportional2, base(), q), 12.0 / 7.0, 12.0 / 7.0);
}

TEST(FusionRules, RejectsWeightsOutsideZeroToOne) {
    RuleParams p;
    p.midpoint_wifi_weight = 1.5;
    EXPECT_THROW(fuse(Rule::midpoint, base(), p), std::invalid_argument);
    p = {};
    p.proportional2_min_r = -0.1;
    EXPECT_THROW(fuse(Rule::proportional2, base(), p), std::invalid_argument);
}

}  // namespace
}  // namespace fusion_rules_test
