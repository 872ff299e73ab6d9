// Kalman and particle filters: a hand-computed Kalman step, convergence on a straight
// corridor with a biased PDR and noisy fixes, and the floor-plan constraints.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "locus/motion/fusion/kalman.hpp"
#include "locus/motion/fusion/particle_filter.hpp"
#include "locus/motion/pdr/heading_convention.hpp"

namespace fusion_filters_test {
namespace {

using locus::Point;
using namespace locus::fusion;

constexpr double kEast = std::numbers::pi / 2.0;  // θ clockwise from +y

Walkable corridor() {
    Walkable w;
    w.plan.width = 60.0;
    w.plan.height = 2.0;
    w.plan.rooms.push_back({1, "corridor", {{0.0, 0.0, 60.0, 2.0}}});
    return w;
}

// Two 5×5 rooms sharing the wall x = 5, with a door only at y ∈ [4, 5] (or none).
Walkable two_rooms(bool door = true) {
    Walkable w;
    w.plan.width = 10.0;
    w.plan.height = 5.0;
    w.plan.rooms.push_back({1, "A", {{0.0, 0.0, 5.0, 5.0}}});
    w.plan.rooms.push_back({2, "B", {{5.0, 0.0, 10.0, 5.0}}});
    if (door) w.doors.push_back({{5.0, 4.0}, {5.0, 5.0}});
    return w;
}

TEST(Kalman, OneStepByHand) {
    KalmanConfig c;
    c.initial_sigma_m = 1.0;  // P = I
    c.step_sigma_floor_m = 0.0;
    c.step_sigma_per_m = 0.0;
    KalmanFilter kf({0.0, 0.0}, c);
    kf.predict({1.0, 0.0});
    EXPECT_DOUBLE_EQ(kf.position().x, 1.0);
    // R = I: K = P(P+R)⁻¹ = ½I, x = (1,0) + ½((3,0) − (1,0)) = (2,0), P = ½I.
    ASSERT_TRUE(kf.update({3.0, 0.0}, Eigen::Matrix2d::Identity()));
    EXPECT_NEAR(kf.position().x, 2.0, 1e-12);
    EXPECT_NEAR(kf.position().y, 0.0, 1e-12);
    EXPECT_NEAR(kf.covariance()(0, 0), 0.5, 1e-12);
    EXPECT_NEAR(kf.covariance()(0, 1), 0.0, 1e-12);
}

TEST(Kalman, PredictGrowsCovarianceWithDistance) {
    KalmanConfig c;
    c.initial_sigma_m = 0.0;
    c.step_sigma_floor_m = 0.1;
    c.step_sigma_per_m = 0.2;
    KalmanFilter kf({0.0, 0.0}, c);
    kf.predict({0.0, 2.0});  // σ = 0.1 + 0.2·2 = 0.5
    EXPECT_NEAR(kf.covariance()(1, 1), 0.25, 1e-12);
}

TEST(Kalman, GateRejectsAnOutlier) {
    KalmanConfig c;
    c.gate_chi2 = 13.8;
    KalmanFilter kf({0.0, 0.0}, c);  // P = I
    EXPECT_FALSE(kf.update({10.0, 0.0}, Eigen::Matrix2d::Identity()));  // d² = 100/2 = 50
    EXPECT_EQ(kf.position().x, 0.0);
    EXPECT_TRUE(kf.update({3.0, 0.0}, Eigen::Matrix2d::Identity()));    // d² = 4.5
}

TEST(Kalman, FixCovarianceFromCandidateSpread) {
    const std::vector<Point> c{{0.0, 0.0}, {2.0, 0.0}};
    const Eigen::Matrix2d r = fix_covariance(c, {}, 0.5);
    EXPECT_NEAR(r(0, 0), 1.0, 1e-12);   // spread ±1 m in x
    EXPECT_NEAR(r(1, 1), 0.25, 1e-12);  // none in y: the floor
    const std::vector<double> w{3.0, 1.0};  // mean 0.5, var = (3·0.25 + 1·2.25)/4 = 0.75
    EXPECT_NEAR(fix_covariance(c, w, 0.1)(0, 0), 0.75, 1e-12);
}

// A straight corridor walked east; the PDR heading is 20° off and steps are 10 % long, as
// in a disturbed area. Fixes every 5 steps are the truth plus 1.5 m noise.
template <typename Filter, typename Step, typename Fix>
static double corridor_final_error(Filter& f, Step step, Fix fix, double* pdr_only_error) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> noise(0.0, 1.5);
    Point truth{1.0, 1.0};
    Point pdr = truth;
    for (int i = 1; i <= 60; ++i) {
        truth = locus::pdr::step(truth, 0.7, kEast);
        const Point before = pdr;
        pdr = locus::pdr::step(pdr, 0.77, kEast + 0.35);
        step(f, before, pdr);
        if (i % 5 == 0) fix(f, Point{truth.x + noise(rng), std::clamp(truth.y + noise(rng), 0.0, 2.0)});
    }
    *pdr_only_error = locus::distance(pdr, truth);
    return locus::distance(f.position(), truth);
}

TEST(Kalman, PullsABiasedPdrBackOnAStraightCorridor) {
    // A constant heading bias is not white noise, so the Kalman filter lags behind it by a
    // bounded amount instead of drifting away like the PDR.
    KalmanFilter kf({1.0, 1.0});
    double pdr_error = 0.0;
    const double err = corridor_final_error(
        kf, [](KalmanFilter& k, Point a, Point b) { k.predict({b.x - a.x, b.y - a.y}); },
        [](KalmanFilter& k, Point z) { k.update(z, Eigen::Matrix2d::Identity() * 2.25); }, &pdr_error);
    EXPECT_GT(pdr_error, 15.0);  // the uncorrected PDR is far off (sanity of the setup)
    EXPECT_LT(err, pdr_error / 4.0);
}

TEST(Kalman, ConvergesFromAWrongStartOnAStraightCorridor) {
    // Start 5 m ahead of the truth with an honest σ; unbiased PDR with 5 cm step noise;
    // fixes every 5 steps with 1.5 m noise. The start error must be forgotten.
    KalmanConfig c;
    c.initial_sigma_m = 5.0;
    c.step_sigma_floor_m = 0.05;  // Q as honest as the PDR here
    c.step_sigma_per_m = 0.05;
    KalmanFilter kf({6.0, 1.0}, c);
    std::mt19937_64 rng(13);
    std::normal_distribution<double> fix_noise(0.0, 1.5), step_noise(0.0, 0.05);
    Point truth{1.0, 1.0};
    double late_error = 0.0;
    for (int i = 1; i <= 60; ++i) {
        const Point next = locus::pdr::step(truth, 0.7, kEast);
        kf.predict({next.x - truth.x + step_noise(rng), next.y - truth.y + step_noise(rng)});
        truth = next;
        if (i % 5 == 0) kf.update({truth.x + fix_noise(rng), truth.y + fix_noise(rng)}, Eigen::Matrix2d::Identity() * 2.25);
        if (i > 40) late_error += locus::distance(kf.position(), truth) / 20.0;
    }
    EXPECT_LT(late_error, 1.0);
}

TEST(ParticleFilter, ConvergesOnAStraightCorridor) {
    ParticleConfig c;
    c.seed = 3;
    ParticleFilter pf(corridor(), {1.0, 1.0}, c);
    double pdr_error = 0.0;
    const double err = corridor_final_error(
        pf, [](ParticleFilter& p, Point, Point) { p.predict(0.77, kEast + 0.35); },
        [](ParticleFilter& p, Point z) { p.update(z, Eigen::Matrix2d::Identity() * 2.25); }, &pdr_error);
    EXPECT_GT(pdr_error, 15.0);
    EXPECT_LT(err, 1.5);
    for (const Particle& p : pf.particles()) EXPECT_TRUE(pf.map().inside(p.at));
}

TEST(Walkable, DoorsAreTheOnlyWayBetweenRooms) {
    const Walkable w = two_rooms();
    EXPECT_TRUE(w.can_move({4.8, 1.0}, {4.9, 1.0}));
    EXPECT_FALSE(w.can_move({4.8, 1.0}, {5.3, 1.0}));   // through the wall
    EXPECT_TRUE(w.can_move({4.8, 4.5}, {5.3, 4.5}));    // through the door
    EXPECT_FALSE(w.can_move({9.8, 1.0}, {10.3, 1.0}));  // off the plan
    Walkable open = w;
    open.walls_between_rooms = false;
    EXPECT_TRUE(open.can_move({4.8, 1.0}, {5.3, 1.0}));
}

TEST(Walkable, ConcaveRoomIsNotCutAcross) {
    Walkable w;
    // An L: a horizontal arm y ∈ [0,2] and a vertical arm x ∈ [0,2] up to y = 10.
    w.plan.rooms.push_back({1, "L", {{0.0, 0.0, 10.0, 2.0}, {0.0, 0.0, 2.0, 10.0}}});
    EXPECT_TRUE(w.can_move({1.0, 5.0}, {1.0, 1.0}));
    EXPECT_FALSE(w.can_move({1.9, 3.0}, {3.0, 1.9}));  // both ends inside, corner cut through the wall
}

TEST(ParticleFilter, ParticlesDoNotCrossWalls) {
    // Walking east into a wall with no door: blocked particles retry other headings and
    // slide along it, but none ever gets into B.
    ParticleFilter pf(two_rooms(false), {2.0, 2.5}, ParticleConfig{});
    for (int i = 0; i < 30; ++i) {
        pf.predict(0.7, kEast);
        for (const Particle& p : pf.particles()) {
            ASSERT_LE(p.at.x, 5.0);
            ASSERT_TRUE(pf.map().inside(p.at));
        }
    }
    // The same walk with a door at the top of the wall: particles find it and pass.
    ParticleFilter through(two_rooms(true), {2.0, 2.5}, ParticleConfig{});
    for (int i = 0; i < 30; ++i) through.predict(0.7, kEast);
    int in_b = 0;
    for (const Particle& p : through.particles()) in_b += p.at.x > 5.0;
    EXPECT_GT(in_b, 100);
}

TEST(ParticleFilter, NeverLeavesTheFloorPlan) {
    ParticleConfig c;
    c.seed = 5;
    c.heading_sigma_rad = 1.0;  // wild headings push particles at every wall
    ParticleFilter pf(two_rooms(), {7.0, 2.5}, c);
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> heading(-std::numbers::pi, std::numbers::pi);
    std::uniform_real_distribution<double> where(-5.0, 15.0);
    for (int i = 0; i < 200; ++i) {
        pf.predict(0.8, heading(rng));
        if (i % 10 == 0) pf.update({where(rng), where(rng)}, Eigen::Matrix2d::Identity() * 4.0);
        for (const Particle& p : pf.particles()) ASSERT_TRUE(pf.map().inside(p.at)) << p.at.x << "," << p.at.y;
    }
}

TEST(ParticleFilter, SameSeedSameTrack) {
    ParticleConfig c;
    c.seed = 42;
    ParticleFilter a(corridor(), {1.0, 1.0}, c), b(corridor(), {1.0, 1.0}, c);
    for (int i = 0; i < 10; ++i) {
        a.predict(0.7, kEast);
        b.predict(0.7, kEast);
    }
    EXPECT_EQ(a.position().x, b.position().x);
    EXPECT_EQ(a.position().y, b.position().y);
}

}  // namespace
}  // namespace fusion_filters_test
