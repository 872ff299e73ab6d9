// The fusion of the Kalman-fusion paper (docs/spec.md §8) on its kind of scenario: BLE anchors
// around a 20 m × 6 m corridor, a walk up and back twice with PDR errors (a fixed step length, its
// noise, heading noise and bias), 1 Hz RSS with 4 dB shadowing. The Kalman filter (PDR as control
// input, multilateration fixes as measurements with their own covariance) must beat both of its
// inputs on the mean error.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "locus/motion/fusion/kalman.hpp"
#include "locus/motion/fusion/ranging_fix.hpp"
#include "locus/ranging/trilateration.hpp"

namespace fusion_ranging_test {
namespace {

using namespace locus;

struct Errors {
    double multilateration = 0, trilateration = 0, pdr = 0, kalman = 0;
};

Errors walk(unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> shadow(0, 4.0), step_noise(0, 0.07), heading_noise(0, 0.05);
    std::vector<ranging::Transmitter> anchors;
    for (double x : {0.0, 5.0, 10.0, 15.0, 20.0})
        for (double y : {0.0, 6.0}) anchors.push_back({{x, y}, 1.5, {-59.0, 2.0}});
    // Truth: twice east along y = 3 to x = 18 and back; one 0.75 m step per second. PDR
    // counts every step as the Kalman-fusion paper's fixed 0.7 m, with a compass 0.08 rad off.
    std::vector<Point> truth;
    for (int lap = 0; lap < 2; ++lap) {
        for (double x = 2; x <= 18; x += 0.75) truth.push_back({x, 3.0});
        for (double x = 18; x >= 2; x -= 0.75) truth.push_back({x, 3.0});
    }
    const double bias = 0.08;
    Point pdr = truth[0];
    fusion::KalmanFilter kf(truth[0]);
    Errors e;
    int fixes = 0, tri = 0;
    for (std::size_t i = 1; i < truth.size(); ++i) {
        const double dx = truth[i].x - truth[i - 1].x, dy = truth[i].y - truth[i - 1].y;
        const double len = std::hypot(dx, dy) > 0 ? 0.7 + step_noise(rng) : 0.0;
        const double heading = std::atan2(dy, dx) + bias + heading_noise(rng);
        const Point step{len * std::cos(heading), len * std::sin(heading)};
        pdr = {pdr.x + step.x, pdr.y + step.y};
        kf.predict(step);
        std::vector<ranging::Heard> heard;
        for (const auto& a : anchors) {
            const double d = std::hypot(std::hypot(truth[i].x - a.at.x, truth[i].y - a.at.y), a.dz);
            heard.push_back({a, ranging::rss_at(a.model, d) + shadow(rng)});
        }
        const auto fix = ranging::multilaterate(heard);
        if (fix) {
            kf.update(fix->at, fusion::ranging_covariance(*fix));
            e.multilateration += distance(fix->at, truth[i]);
            ++fixes;
        }
        if (const auto t = ranging::trilaterate(heard)) {
            e.trilateration += distance(t->at, truth[i]);
            ++tri;
        }
        e.pdr += distance(pdr, truth[i]);
        e.kalman += distance(kf.position(), truth[i]);
    }
    const double steps = static_cast<double>(truth.size() - 1);
    e.multilateration /= fixes;
    e.trilateration /= std::max(tri, 1);
    e.pdr /= steps;
    e.kalman /= steps;
    return e;
}

TEST(FusionRanging, KalmanBeatsItsInputsOverTwentyWalks) {
    Errors mean;
    for (unsigned seed = 1; seed <= 20; ++seed) {
        const auto e = walk(seed);
        mean.multilateration += e.multilateration / 20;
        mean.trilateration += e.trilateration / 20;
        mean.pdr += e.pdr / 20;
        mean.kalman += e.kalman / 20;
    }
    std::printf("mean error over 20 walks: trilateration %.2f m, multilateration %.2f m, PDR %.2f m, Kalman %.2f m\n",
                mean.trilateration, mean.multilateration, mean.pdr, mean.kalman);
    EXPECT_LT(mean.kalman, mean.multilateration);
    EXPECT_LT(mean.kalman, mean.pdr);
    EXPECT_LT(mean.multilateration, mean.trilateration);
}

TEST(FusionRanging, CovarianceHasAFloorAndStaysFinite) {
    ranging::Fix f;
    f.sxx = 0.0;
    f.syy = 4.0;
    f.sxy = 0.5;
    const auto r = fusion::ranging_covariance(f, 0.5);
    EXPECT_DOUBLE_EQ(r(0, 0), 0.25);
    EXPECT_DOUBLE_EQ(r(1, 1), 4.25);
    EXPECT_DOUBLE_EQ(r(0, 1), 0.5);
    f.sxx = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(std::isfinite(fusion::ranging_covariance(f).determinant()));
}

TEST(FusionRanging, MeasurementNoiseIsConfiguredOrTheFixs) {
    ranging::Fix f;
    f.sxx = 4.0;
    f.syy = 1.0;
    f.sxy = 0.5;
    fusion::RangingKalmanConfig fixed;
    fixed.fixed_r_sigma_m = 2.0;  // the Kalman-fusion paper: R a constant, whatever the fix claims
    EXPECT_TRUE(fusion::ranging_measurement_noise(f, fixed).isApprox(Eigen::Matrix2d::Identity() * 4.0));
    fusion::RangingKalmanConfig own;
    own.r_floor_m = 0.0;
    own.r_scale = 2.0;
    const Eigen::Matrix2d r = fusion::ranging_measurement_noise(f, own);
    EXPECT_DOUBLE_EQ(r(0, 0), 8.0);
    EXPECT_DOUBLE_EQ(r(1, 1), 2.0);
    EXPECT_DOUBLE_EQ(r(0, 1), 1.0);
    // The paper's filter: constant Q per step (no growth with the distance walked) and a fixed R.
    const auto constant = fusion::trilateration_kalman_config();
    EXPECT_GT(constant.fixed_r_sigma_m, 0.0);
    EXPECT_EQ(constant.kalman.step_sigma_per_m, 0.0);
    fusion::KalmanFilter kf({0, 0}, constant.kalman);
    kf.predict({0.1, 0.0});
    const double after_short = kf.covariance()(0, 0);
    fusion::KalmanFilter kf2({0, 0}, constant.kalman);
    kf2.predict({1.0, 0.0});
    EXPECT_DOUBLE_EQ(kf2.covariance()(0, 0), after_short);
}

}  // namespace
}  // namespace fusion_ranging_test
