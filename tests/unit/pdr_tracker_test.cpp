#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "locus/motion/pdr/pipeline.hpp"
#include "locus/motion/pdr/tracker.hpp"

namespace pdr_tracker_test {
namespace {

using namespace locus;
using namespace locus::pdr;

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.80665;

StepLengthModel constant(double m) {
    StepLengthModel s;
    s.kind = StepLengthKind::constant;
    s.constant_m = m;
    return s;
}

FloorPlan two_rooms() {
    FloorPlan p;
    p.width = 20;
    p.height = 10;
    p.rooms.push_back({1, "West", {{0, 0, 10, 10}}});
    p.rooms.push_back({2, "East", {{10, 0, 20, 10}}});
    p.pois.push_back({1, "Exit", "exit", {12.0, 2.0}});
    return p;
}

TEST(Tracker, StepsFollowTheSpecConvention) {
    Tracker t({5, 5}, nullptr, constant(0.7));
    auto p = t.on_step({}, 0.0);  // θ = 0: along +y
    EXPECT_NEAR(p.position.x, 5.0, 1e-12);
    EXPECT_NEAR(p.position.y, 5.7, 1e-12);
    p = t.on_step({}, kPi / 2);  // θ = 90°: along +x (clockwise from +y)
    EXPECT_NEAR(p.position.x, 5.7, 1e-12);
    EXPECT_NEAR(p.position.y, 5.7, 1e-12);
    EXPECT_EQ(t.steps(), 2u);
    EXPECT_NEAR(t.distance_m(), 1.4, 1e-12);
}

TEST(Tracker, SquareWalkCloses) {
    Tracker t({3, 4}, nullptr, constant(0.7));
    for (double heading : {0.0, kPi / 2, kPi, -kPi / 2})
        for (int i = 0; i < 10; ++i) t.on_step({}, heading);
    EXPECT_NEAR(t.position().x, 3.0, 1e-9);
    EXPECT_NEAR(t.position().y, 4.0, 1e-9);
    EXPECT_NEAR(t.distance_m(), 28.0, 1e-9);
}

TEST(Tracker, RoomPoisAndDisturbanceFlag) {
    const FloorPlan plan = two_rooms();
    Tracker t({8.6, 2.0}, &plan, constant(0.7));
    ASSERT_NE(t.room(), nullptr);
    EXPECT_EQ(t.room()->name, "West");
    EXPECT_TRUE(t.nearby_pois().empty());  // 3.4 m from the exit
    t.on_step({}, kPi / 2, true);          // x = 9.3
    EXPECT_TRUE(t.magnetic_disturbance());
    t.on_step({}, kPi / 2);                // x = 10.0: on the shared wall, first room wins
    EXPECT_EQ(t.room()->name, "West");
    t.on_step({}, kPi / 2);                // x = 10.7: 1.3 m from the exit, within 1.5 m
    EXPECT_FALSE(t.magnetic_disturbance());
    EXPECT_EQ(t.room()->name, "East");
    ASSERT_EQ(t.nearby_pois().size(), 1u);
    EXPECT_EQ(t.nearby_pois()[0]->name, "Exit");
    t.set_position({30, 30});
    EXPECT_EQ(t.room(), nullptr);
}

// The whole chain on a simulated 50 Hz IMU: a flat phone, +y forward, walks 20 steps along each
// side of a square turning 90° clockwise on the spot between sides, with gyro and compass
// telling the same story. The track must close and count every step.
TEST(Pipeline, SimulatedSquareWalkCloses) {
    const double rate = 50.0, dt = 1.0 / rate, step_hz = 1.8;
    const Vec3 field_world{0.0, 22.0, -42.0};  // x east, y north, z up
    PipelineConfig pc;
    pc.start = {10, 10};
    Pipeline p(pc);
    double t = 0.0, psi = 0.0;
    auto sample = [&](double av, double yaw_rate) {
        t += dt;
        // Device frame = world rotated by psi clockwise about up.
        const double c = std::cos(psi), s = std::sin(psi);
        const Vec3 mag{c * field_world.x - s * field_world.y, s * field_world.x + c * field_world.y, field_world.z};
        p.push_gyro(t, {0, 0, -yaw_rate});  // clockwise turn = negative rate about +z (up)
        p.push_mag(t, mag);
        p.push_accel(t, {0, 0, kG + av});
    };
    auto still = [&](double seconds) {
        for (int i = 0; i < seconds * rate; ++i) sample(0.0, 0.0);
    };
    still(3.0);
    for (int side = 0; side < 4; ++side) {
        const int n = static_cast<int>(std::lround(20 / step_hz * rate));
        for (int i = 0; i < n; ++i) sample(2.0 * std::sin(2 * kPi * step_hz * (i + 1) * dt), 0.0);
        still(1.5);
        if (side < 3) {
            for (int i = 0; i < rate; ++i) {
                psi += (kPi / 2) / rate;
                sample(0.0, kPi / 2);
            }
            still(1.5);
        }
    }
    while (p.poll()) {
    }
    EXPECT_EQ(p.tracker().steps(), 80u);
    const double walked = p.tracker().distance_m();
    EXPECT_GT(walked, 40.0);  // Weinberg with K = 0.52 on a ~4 m/s² peak-to-peak: ~0.7 m a step
    const double gap = distance(p.tracker().position(), pc.start);
    EXPECT_LT(gap, 0.01 * walked) << "end " << p.tracker().position().x << "," << p.tracker().position().y;
}

// The detector confirms a walking bout only after several steps, so the first steps come out
// late; they must still be placed with the heading the walker had when taking them.
TEST(Pipeline, DelayedBoutStepsUseTheHeadingAtTheirTime) {
    const double rate = 100.0, dt = 1.0 / rate, step_hz = 2.0;
    const StepDetectorConfig sc;
    ASSERT_GE(sc.bout_steps, 4) << "test assumes a bout needs at least 4 steps";
    PipelineConfig pc;
    pc.step_length.kind = StepLengthKind::constant;
    pc.step_length.constant_m = 0.7;
    Pipeline p(pc);
    const Vec3 field_world{0.0, 22.0, -42.0};
    double t = 0.0, psi = 0.0;
    auto sample = [&](double av, double yaw_rate) {
        t += dt;
        const double c = std::cos(psi), s = std::sin(psi);
        p.push_gyro(t, {0, 0, -yaw_rate});
        p.push_mag(t, {c * field_world.x - s * field_world.y, s * field_world.x + c * field_world.y, field_world.z});
        p.push_accel(t, {0, 0, kG + av});
    };
    for (int i = 0; i < 3 * rate; ++i) sample(0.0, 0.0);
    // Two steps north, a quick 90° turn to the east while still stepping, then 18 steps east.
    const int per_step = static_cast<int>(rate / step_hz);
    const int turn_samples = 10;  // 0.1 s, inside the third step
    for (int k = 0; k < 20 * per_step; ++k) {
        const bool turning = k >= 2 * per_step && k < 2 * per_step + turn_samples;
        if (turning) psi += (kPi / 2) / turn_samples;
        sample(2.0 * std::sin(2 * kPi * step_hz * (k + 1) * dt), turning ? (kPi / 2) / (turn_samples * dt) : 0.0);
    }
    for (int i = 0; i < 2 * rate; ++i) sample(0.0, 0.0);
    while (p.poll()) {
    }
    ASSERT_EQ(p.tracker().steps(), 20u);
    // The first two steps (valleys at 0.375 s and 0.875 s) went north; the turn starts at 1.0 s.
    EXPECT_NEAR(p.tracker().position().y, 2 * 0.7, 0.15);
    EXPECT_NEAR(p.tracker().position().x, 18 * 0.7, 0.15);
}

TEST(Pipeline, PlatformStepsUseTheCurrentHeading) {
    PipelineConfig pc;
    pc.start = {1, 1};
    pc.start_heading_rad = kPi / 2;  // no compass yet: the start heading is used
    pc.step_length.kind = StepLengthKind::constant;
    pc.step_length.constant_m = 0.5;
    Pipeline p(pc);
    auto tp = p.push_platform_step(0.5);
    EXPECT_NEAR(tp.position.x, 1.5, 1e-12);
    EXPECT_NEAR(tp.position.y, 1.0, 1e-12);
    tp = p.push_platform_step(1.0);
    EXPECT_NEAR(tp.position.x, 2.0, 1e-12);
    EXPECT_EQ(p.tracker().steps(), 2u);
    EXPECT_EQ(p.step_detector().steps(), 2u);
}

}  // namespace
}  // namespace pdr_tracker_test
