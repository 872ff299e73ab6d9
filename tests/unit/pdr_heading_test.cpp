#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "locus/motion/pdr/compass.hpp"
#include "locus/motion/pdr/heading_convention.hpp"
#include "locus/motion/pdr/heading_estimator.hpp"

namespace pdr_heading_test {
namespace {

using namespace locus::pdr;

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.80665;
double deg(double d) { return d * kPi / 180.0; }

// World frame: x east, y north, z up. A field of 50 µT dipping 63° (central Europe).
const Vec3 kField{0.0, 50.0 * std::cos(deg(63)), -50.0 * std::sin(deg(63))};

struct Mat {
    Vec3 c0, c1, c2;  // columns: device x, y, z axes in world coordinates
};
Vec3 apply(const Mat& m, Vec3 v) { return v.x * m.c0 + v.y * m.c1 + v.z * m.c2; }
Mat mul(const Mat& a, const Mat& b) { return {apply(a, b.c0), apply(a, b.c1), apply(a, b.c2)}; }
Vec3 to_device(const Mat& r, Vec3 w) { return {dot(r.c0, w), dot(r.c1, w), dot(r.c2, w)}; }

Mat rot_x(double a) { return {{1, 0, 0}, {0, std::cos(a), std::sin(a)}, {0, -std::sin(a), std::cos(a)}}; }
Mat rot_y(double a) { return {{std::cos(a), 0, -std::sin(a)}, {0, 1, 0}, {std::sin(a), 0, std::cos(a)}}; }
Mat rot_z(double a) { return {{std::cos(a), std::sin(a), 0}, {-std::sin(a), std::cos(a), 0}, {0, 0, 1}}; }

// Device whose +y points at azimuth psi (clockwise from north), pitched up by pitch about its x
// axis and rolled by roll about its y axis.
Mat pose(double psi, double pitch = 0.0, double roll = 0.0) { return mul(rot_z(-psi), mul(rot_x(pitch), rot_y(roll))); }

Vec3 gravity_reading(const Mat& r) { return to_device(r, {0, 0, kG}); }
Vec3 field_reading(const Mat& r) { return to_device(r, kField); }

double angle_diff(double a, double b) { return std::abs(wrap_angle(a - b)); }

TEST(Compass, HandComputedFlatCases) {
    // Flat, screen up, +y to magnetic north.
    auto a = compass_azimuth({0, 0, kG}, {0, 20, -40});
    ASSERT_TRUE(a);
    EXPECT_NEAR(*a, 0.0, 1e-12);
    // North along device +x: +y points 90° anticlockwise of north, i.e. west.
    a = compass_azimuth({0, 0, kG}, {20, 0, -40});
    ASSERT_TRUE(a);
    EXPECT_NEAR(*a, -kPi / 2, 1e-12);
}

TEST(Compass, FlatTiltedAndUpsideDownInSeveralFields) {
    // Equator (horizontal field), Europe (dip 63°), near the pole (dip 80°), southern
    // hemisphere (field pointing up), and a weak 25 µT field.
    const Vec3 fields[] = {{0, 35, 0}, kField, {0, 50 * std::cos(deg(80)), -50 * std::sin(deg(80))},
                           {0, 30 * std::cos(deg(50)), 30 * std::sin(deg(50))}, {0, 12, -21.9}};
    for (const Vec3& f : fields) {
        for (double psi : {0.0, 30.0, 90.0, 179.0, -135.0, -60.0}) {
            for (double pitch : {0.0, 25.0, -40.0, 60.0}) {
                for (double roll : {0.0, 20.0, -35.0, 180.0}) {
                    const Mat r = pose(deg(psi), deg(pitch), deg(roll));
                    const auto a = compass_azimuth(gravity_reading(r), to_device(r, f));
                    ASSERT_TRUE(a);
                    EXPECT_LT(angle_diff(*a, deg(psi)), 1e-9)
                        << psi << " " << pitch << " " << roll << " field " << f.y << "," << f.z;
                }
            }
        }
    }
}

TEST(Compass, UprightPhoneUsesTheBackOfTheDevice) {
    // Held upright in portrait, screen to the user: +y is vertical, the camera (−z) looks ahead.
    for (double psi : {0.0, 45.0, -100.0}) {
        const Mat r = pose(deg(psi), deg(90));
        const auto a = compass_azimuth(gravity_reading(r), field_reading(r));
        ASSERT_TRUE(a);
        EXPECT_LT(angle_diff(*a, deg(psi)), 1e-9) << psi;
    }
}

TEST(Compass, DegenerateInputs) {
    EXPECT_FALSE(compass_azimuth({0, 0, 0.1}, {0, 20, -40}));   // free fall
    EXPECT_FALSE(compass_azimuth({0, 0, kG}, {0, 0, -45}));     // field along gravity (a magnetic pole)
}

TEST(LowPass3, SeedFilter) {
    LowPass3 lp(0.2);
    lp.push({10, 0, 0});
    const auto v = lp.push({0, 10, 0});
    EXPECT_DOUBLE_EQ(v.x, 8.0);
    EXPECT_DOUBLE_EQ(v.y, 2.0);
}

// Feeds a static device at azimuth psi for `seconds` at `rate` Hz (all three sensors), gyro w.
void feed(HeadingEstimator& h, double& t, double seconds, double rate, const Mat& r, Vec3 w = {}, double field_scale = 1.0) {
    const int n = static_cast<int>(std::lround(seconds * rate));
    for (int i = 0; i < n; ++i) {
        t += 1.0 / rate;
        h.push_accel(t, gravity_reading(r));
        h.push_mag(t, field_scale * field_reading(r));
        h.push_gyro(t, w);
    }
}

TEST(HeadingEstimator, ComplementaryFilterCrossesTheWrapTheShortWay) {
    HeadingEstimator h;
    double t = 0.0;
    feed(h, t, 2.0, 50.0, pose(deg(179)));
    ASSERT_TRUE(h.heading());
    EXPECT_LT(angle_diff(*h.heading(), deg(179)), 1e-6);
    // The compass now reads 181° = −179°: 2° clockwise, across ±180°. A filter that averages
    // raw angles would swing through 0° (0.95·179 + 0.05·(−179) = 161 after one update).
    const Mat r = pose(deg(-179));
    for (int i = 0; i < 250; ++i) {
        feed(h, t, 0.02, 50.0, r);
        ASSERT_GT(std::abs(*h.heading()), deg(178.99)) << "step " << i;
    }
    EXPECT_LT(angle_diff(*h.heading(), deg(-179)), deg(0.01));
    EXPECT_FALSE(h.magnetic_disturbance());
}

TEST(HeadingEstimator, CompassWeightIsPerTwentyMillisecondsAtAnyRate) {
    // Compass at 90°, fused heading forced to 0, gyro still: after 0.5 s the heading is
    // 90°·(1 − 0.95^(0.5/0.02)) = 65.03° whatever the sensor rate.
    for (double rate : {50.0, 100.0, 400.0}) {
        HeadingEstimator h;
        double t = 0.0;
        const Mat r = pose(deg(90));
        feed(h, t, 0.1, rate, r);
        h.set_heading(0.0);
        feed(h, t, 0.5, rate, r);
        EXPECT_NEAR(*h.heading() * 180.0 / kPi, 90.0 * (1.0 - std::pow(0.95, 25.0)), 0.05) << rate << " Hz";
    }
}

TEST(HeadingEstimator, GyroTurnsAreClockwisePositive) {
    HeadingConfig c;
    c.compass_weight = 0.0;
    for (bool upside_down : {false, true}) {
        HeadingEstimator h(c);
        double t = 0.0;
        const Mat r = pose(0.0, 0.0, upside_down ? kPi : 0.0);
        feed(h, t, 0.5, 100.0, r);
        // +0.5 rad/s about device z for 2 s: anticlockwise seen from above when the screen is up
        // (heading −1 rad), clockwise when the screen faces the floor (+1 rad).
        feed(h, t, 2.0, 100.0, r, {0, 0, 0.5});
        EXPECT_NEAR(*h.heading(), upside_down ? 1.0 : -1.0, 1e-9);
    }
}

TEST(HeadingEstimator, FieldMagnitudeDisturbanceDropsTheCompass) {
    HeadingEstimator h;
    double t = 0.0;
    feed(h, t, 3.0, 50.0, pose(deg(10)));
    EXPECT_FALSE(h.magnetic_disturbance());
    // A steel door: the field is 60 % stronger and points elsewhere.
    feed(h, t, 2.0, 50.0, pose(deg(80)), {}, 1.6);
    EXPECT_TRUE(h.magnetic_disturbance());
    EXPECT_LT(angle_diff(*h.heading(), deg(10)), deg(0.5)) << "the heading must not follow a lying compass";
    // Back in a clean field the magnitude test passes at once; the gyro/compass test clears once
    // a whole window (1 s) has seen them agree, so the jump back itself is not trusted either.
    feed(h, t, 2.5, 50.0, pose(deg(10)));
    EXPECT_FALSE(h.magnetic_disturbance());
}

TEST(HeadingEstimator, GyroCompassDisagreementIsFlagged) {
    HeadingEstimator h;
    double t = 0.0;
    feed(h, t, 3.0, 50.0, pose(0.0));
    // Same field strength but the compass swings 90° while the gyro reports no rotation.
    feed(h, t, 1.5, 50.0, pose(deg(90)));
    EXPECT_TRUE(h.magnetic_disturbance());
    // A real turn (gyro and compass agree) is not a disturbance.
    HeadingEstimator g;
    t = 0.0;
    feed(g, t, 3.0, 50.0, pose(0.0));
    for (int i = 0; i < 50; ++i) feed(g, t, 0.02, 50.0, pose(deg(90.0 * (i + 1) / 50.0)), {0, 0, -deg(90)});
    feed(g, t, 2.0, 50.0, pose(deg(90)));
    EXPECT_FALSE(g.magnetic_disturbance());
    EXPECT_LT(angle_diff(*g.heading(), deg(90)), deg(1));
}

TEST(HeadingEstimator, NorthOffsetAndLocalNorthCalibration) {
    HeadingConfig c;
    c.north_offset_deg = 30.0;  // the floor's +y is 30° clockwise of magnetic north
    HeadingEstimator h(c);
    double t = 0.0;
    feed(h, t, 2.0, 50.0, pose(deg(30)));
    EXPECT_LT(angle_diff(*h.heading(), 0.0), 1e-6);
    feed(h, t, 5.0, 50.0, pose(deg(120)));  // the compass jump is flagged, so feed long enough
    feed(h, t, 5.0, 50.0, pose(deg(120)));
    // The user lines the phone up with the corridor, which the map says runs at 80°.
    h.calibrate_local_north(deg(80));
    EXPECT_LT(angle_diff(*h.heading(), deg(80)), 1e-9);
    h.set_north_offset_deg(0.0);
    // Without the floor offset the same calibration still holds relative to the new frame.
    EXPECT_LT(angle_diff(*h.heading(), deg(110)), 1e-9);
}

}  // namespace
}  // namespace pdr_heading_test
