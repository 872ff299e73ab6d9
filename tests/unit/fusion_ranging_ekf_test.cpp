// The tightly coupled ranging filter (fusion::RangingEkf) on cases whose answer is known:
// noise-free readings of a static phone, a phone whose radio adds a constant offset, a PDR
// whose heading is off by a constant, a glitch and readings of unknown anchors.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "locus/motion/fusion/ranging_ekf.hpp"
#include "locus/ranging/path_loss.hpp"

namespace fusion_ranging_ekf_test {
namespace {

using namespace locus;
using namespace locus::fusion;

// Six anchors around a 20 m × 8 m room, 1.3 m above the phone (the Kalman-fusion paper's kind of
// layout).
std::vector<RangingAnchor> six_anchors() {
    std::vector<RangingAnchor> out;
    const Point at[] = {{0, 0}, {10, 0}, {20, 0}, {0, 8}, {10, 8}, {20, 8}};
    const char* ids[] = {"a0", "a1", "a2", "a3", "a4", "a5"};
    for (int i = 0; i < 6; ++i) out.push_back({ids[i], {at[i], 1.3, {-59.0, 2.0}}});
    return out;
}

// What each anchor is heard at from p, plus `offset` dB.
std::vector<AnchorReading> scan_at(const std::vector<RangingAnchor>& anchors, Point p, double t, double offset = 0.0) {
    std::vector<AnchorReading> out;
    for (const RangingAnchor& a : anchors) {
        const double d = std::hypot(std::hypot(p.x - a.tx.at.x, p.y - a.tx.at.y), a.tx.dz);
        out.push_back({a.id, t, ranging::rss_at(a.tx.model, d) + offset});
    }
    return out;
}

TEST(RangingEkf, StaticPhoneNoiseFreeConvergesToTheTruth) {
    const auto anchors = six_anchors();
    const Point truth{13.0, 3.0};
    RangingEkfConfig cfg;
    cfg.initial_sigma_m = 3.0;
    RangingEkf ekf({10.0, 5.0}, anchors, cfg);  // starts 3.6 m off
    for (int t = 0; t < 60; ++t) EXPECT_EQ(ekf.update(scan_at(anchors, truth, t)), 6);
    EXPECT_LT(distance(ekf.position(), truth), 0.05);
    EXPECT_NEAR(ekf.offset_db(), 0.0, 0.2);
    // The covariance shrank from the prior's 9 m² per axis.
    EXPECT_LT(ekf.position_covariance().trace(), 1.0);
}

TEST(RangingEkf, LearnsAConstantPhoneOffset) {
    const auto anchors = six_anchors();
    const Point truth{6.0, 4.0};
    RangingEkf ekf(truth, anchors);
    for (int t = 0; t < 60; ++t) ekf.update(scan_at(anchors, truth, t, 5.0));
    EXPECT_NEAR(ekf.offset_db(), 5.0, 0.2);
    EXPECT_LT(distance(ekf.position(), truth), 0.1);
    // Without the offset in the state a +5 dB phone is taken as nearer to every anchor at once,
    // which no position explains; the state's offset is what keeps the fix.
    RangingEkfConfig no_offset;
    no_offset.offset_sigma_db = 0.0;
    RangingEkf blind(truth, anchors, no_offset);
    for (int t = 0; t < 60; ++t) blind.update(scan_at(anchors, truth, t, 5.0));
    EXPECT_NEAR(blind.offset_db(), 0.0, 1e-9);
}

TEST(RangingEkf, WalkWithABiasedCompassLearnsTheBias) {
    // The person walks along y = 4 (heading 0); the PDR says 0.15 rad to the right of that.
    const auto anchors = six_anchors();
    const double bias = 0.15;
    Point truth{1.0, 4.0};
    RangingEkfConfig cfg;
    cfg.step_lead_s = 0.0;  // these steps are made when stamped
    RangingEkf ekf(truth, anchors, cfg);
    double t = 0.0;
    Point dead_reckoned = truth;
    for (int step = 0; step < 36; ++step) {
        truth.x += 0.5;
        t += 0.5;
        const Point pdr{0.5 * std::cos(-bias), 0.5 * std::sin(-bias)};
        dead_reckoned.x += pdr.x;
        dead_reckoned.y += pdr.y;
        ekf.predict(pdr, t);
        if (step % 2 == 1) ekf.update(scan_at(anchors, truth, t));
    }
    EXPECT_NEAR(ekf.heading_bias_rad(), bias, 0.05);
    // Dead reckoning alone ends 18 m × sin(0.15) ≈ 2.7 m off.
    EXPECT_GT(distance(dead_reckoned, truth), 2.5);
    EXPECT_LT(distance(ekf.position(), truth), 0.5);
}

TEST(RangingEkf, AGlitchAndUnknownAnchorsDoNotMoveAStaticPhone) {
    const auto anchors = six_anchors();
    const Point truth{10.0, 4.0};
    RangingEkf ekf(truth, anchors);
    for (int t = 0; t < 20; ++t) ekf.update(scan_at(anchors, truth, t));
    auto glitch = scan_at(anchors, truth, 20);
    glitch[0].rss = 0.0;                            // 0 dBm from an anchor 10 m away
    glitch.push_back({"somebody-else", 20, -30.0});  // not one of the floor's anchors
    EXPECT_EQ(ekf.update(glitch), 6);
    EXPECT_LT(distance(ekf.position(), truth), 0.5);
    EXPECT_EQ(ekf.update(std::vector<AnchorReading>{{"nobody", 21, -50.0}}), 0);
}

TEST(RangingEkf, AReadingIsTakenWhereThePhoneWasBeforeTheStepsStampedAhead) {
    // A step stamped at t = 10 s that the phone makes over the next 0.7 s: readings at 10.2 s
    // still come from where it stood. With the lead the filter keeps the step; without, the
    // readings pull it back toward the old position.
    const auto anchors = six_anchors();
    const Point before{8.0, 4.0}, after{8.7, 4.0};
    auto run = [&](double lead) {
        RangingEkfConfig cfg;
        cfg.step_lead_s = lead;
        RangingEkf ekf(before, anchors, cfg);
        for (int t = 0; t < 10; ++t) ekf.update(scan_at(anchors, before, t));
        ekf.predict({0.7, 0.0}, 10.0);
        for (int k = 0; k < 10; ++k) ekf.update(scan_at(anchors, before, 10.2 + 0.05 * k));
        return ekf.position();
    };
    EXPECT_LT(distance(run(0.7), after), 0.05);
    EXPECT_GT(distance(run(0.0), after), 0.2);
}

TEST(RangingEkf, PositionFixIsAWeightedMeanOfPriorAndFix) {
    const auto anchors = six_anchors();
    RangingEkfConfig cfg;
    cfg.initial_sigma_m = 2.0;  // prior variance 4 m² per axis
    RangingEkf ekf({0.0, 0.0}, anchors, cfg);
    // Fix variance 4 m² too: halfway, and half the variance.
    ekf.update_position({4.0, -2.0}, Eigen::Matrix2d::Identity() * 4.0);
    EXPECT_NEAR(ekf.position().x, 2.0, 1e-12);
    EXPECT_NEAR(ekf.position().y, -1.0, 1e-12);
    EXPECT_NEAR(ekf.position_covariance()(0, 0), 2.0, 1e-12);
    EXPECT_NEAR(ekf.offset_db(), 0.0, 1e-12);  // uncorrelated with the position yet: untouched
    // A far surer fix wins.
    ekf.update_position({10.0, 10.0}, Eigen::Matrix2d::Identity() * 1e-4);
    EXPECT_LT(distance(ekf.position(), {10.0, 10.0}), 0.01);
}

// A config that would divide by zero in the update is refused when the filter is made.
TEST(RangingEkf, RefusesAConfigThatWouldTurnTheStateNaN) {
    const std::vector<RangingAnchor> none;
    for (auto broken : {+[](RangingEkfConfig& c) { c.reading_sigma_db = 0.0; }, +[](RangingEkfConfig& c) { c.huber_k = -1.0; },
                        +[](RangingEkfConfig& c) { c.min_range_m = 0.0; }, +[](RangingEkfConfig& c) { c.iterations = 0; }}) {
        RangingEkfConfig c;
        broken(c);
        EXPECT_THROW(RangingEkf({0.0, 0.0}, none, c), std::invalid_argument);
    }
    EXPECT_NO_THROW(RangingEkf({0.0, 0.0}, none, RangingEkfConfig{}));
}

}  // namespace
}  // namespace fusion_ranging_ekf_test
