#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "locus/motion/pdr/step_detector.hpp"
#include "locus/motion/pdr/vec3.hpp"

namespace pdr_step_detector_test {
namespace {

using namespace locus::pdr;

constexpr double kG = 9.80665;
constexpr double kPi = std::numbers::pi;

struct Walk {
    double rate_hz = 100.0;
    double jitter = 0.0;        // timestamps move by up to ±jitter of the nominal period
    double noise = 0.0;         // m/s², per axis, Gaussian
    double step_hz = 1.8;
    double amplitude = 2.0;     // m/s² of the vertical oscillation
    double harmonic = 0.0;      // relative second-harmonic content (heel strike shape)
    Vec3 up{0.0, 0.0, 1.0};     // where gravity's reaction points in the device frame
    unsigned seed = 1;
};

// Still for 1.5 s, `steps` full cycles of vertical oscillation (one cycle = one step, its valley
// at 3/4 of the cycle), still for 1.5 s. Returns the number of samples pushed; records the true
// valley times.
struct Run {
    std::vector<StepEvent> events;
    std::vector<double> valleys;
};

Run walk(StepDetector& d, const Walk& w, int steps, double t_start = 0.0) {
    std::mt19937 rng(w.seed);
    std::normal_distribution<double> noise(0.0, w.noise);
    std::uniform_real_distribution<double> jit(-w.jitter, w.jitter);
    const double un = norm(w.up);
    const Vec3 u = (1.0 / un) * w.up;
    const double walk_start = t_start + 1.5;
    const double walk_end = walk_start + steps / w.step_hz;
    const double end = walk_end + 1.5;
    Run r;
    for (int i = 0; i < steps; ++i) r.valleys.push_back(walk_start + (i + 0.75) / w.step_hz);
    const double dt = 1.0 / w.rate_hz;
    for (double tn = t_start; tn < end; tn += dt) {
        const double t = tn + jit(rng) * dt;
        double av = 0.0;
        if (t > walk_start && t < walk_end) {
            const double ph = 2.0 * kPi * w.step_hz * (t - walk_start);
            // The harmonic is a cosine at twice the rate so that it sharpens the peak and valley
            // without adding extrema of its own at the level used here.
            av = w.amplitude * (std::sin(ph) - w.harmonic * std::cos(2.0 * ph) + w.harmonic);
        }
        const Vec3 a = (kG + av) * u + Vec3{noise(rng), noise(rng), noise(rng)};
        if (auto e = d.push(t, a.x, a.y, a.z)) r.events.push_back(*e);
    }
    while (auto e = d.poll()) r.events.push_back(*e);
    return r;
}

TEST(StepDetector, CountsSyntheticWalkAtSeveralRatesAndNoiseLevels) {
    for (double rate : {50.0, 100.0, 200.0, 400.0}) {
        for (double noise : {0.0, 0.3, 0.6}) {
            StepDetector d;
            Walk w;
            w.rate_hz = rate;
            w.noise = noise;
            const auto r = walk(d, w, 40);
            EXPECT_EQ(d.steps(), 40u) << rate << " Hz, noise " << noise;
            EXPECT_EQ(r.events.size(), 40u) << rate << " Hz, noise " << noise;
        }
    }
}

TEST(StepDetector, StepTimesAreTheValleysAndAmplitudeIsPeakToPeak) {
    StepDetector d;
    Walk w;
    w.rate_hz = 200.0;
    const auto r = walk(d, w, 20);
    ASSERT_EQ(r.events.size(), 20u);
    for (std::size_t i = 0; i < r.events.size(); ++i) {
        EXPECT_NEAR(r.events[i].t_s, r.valleys[i], 0.05) << "step " << i;
        // Peak-to-peak of a 2 m/s² sine is 4 m/s²; smoothing and gravity tracking change it by
        // less than 20 % (moving-average gain at 1.8 Hz ≈ 0.97).
        EXPECT_NEAR(r.events[i].amplitude(), 4.0, 0.8) << "step " << i;
        EXPECT_GT(r.events[i].a_max, 0.0);
        EXPECT_LT(r.events[i].a_min, 0.0);
    }
}

TEST(StepDetector, IrregularTimestampsAndDuplicates) {
    for (double rate : {50.0, 400.0}) {
        StepDetector d;
        Walk w;
        w.rate_hz = rate;
        w.jitter = 0.45;  // consecutive samples may swap order: those going back are ignored
        w.noise = 0.3;
        w.harmonic = 0.3;
        walk(d, w, 30);
        EXPECT_EQ(d.steps(), 30u) << rate << " Hz";
    }
}

TEST(StepDetector, AnyDeviceOrientationWithVerticalOrMagnitudeSignal) {
    const Vec3 orientations[] = {{0, 0, 1}, {0, 0, -1}, {0, 1, 0}, {1, -2, 3}, {-0.3, 0.2, -1}};
    for (auto signal : {StepSignal::vertical, StepSignal::magnitude}) {
        for (const auto& up : orientations) {
            StepDetectorConfig c;
            c.signal = signal;
            StepDetector d(c);
            Walk w;
            w.up = up;
            w.noise = 0.2;
            walk(d, w, 25);
            EXPECT_EQ(d.steps(), 25u) << "up (" << up.x << "," << up.y << "," << up.z << ")";
        }
    }
}

TEST(StepDetector, StillPhoneCountsNothing) {
    StepDetector d;
    Walk w;
    w.noise = 0.3;
    walk(d, w, 0);
    std::mt19937 rng(7);
    std::normal_distribution<double> n(0.0, 0.3);
    for (int i = 0; i < 6000; ++i) d.push(3.0 + i * 0.01, n(rng), n(rng), kG + n(rng));
    EXPECT_EQ(d.steps(), 0u);
}

TEST(StepDetector, AtMostOneStepPer250ms) {
    // Shaking at 6 Hz for 5 s: without the timing gate every cycle would count (30).
    StepDetector d;
    Walk w;
    w.step_hz = 6.0;
    w.amplitude = 5.0;
    walk(d, w, 30);
    EXPECT_LE(d.steps(), 20u);
}

TEST(StepDetector, GapInTheLogRestartsFiltersButKeepsCount) {
    StepDetector d;
    Walk w;
    walk(d, w, 20, 0.0);
    // A 3 s hole, then a second walk.
    const double t2 = 1.5 + 20 / 1.8 + 1.5 + 3.0;
    walk(d, w, 15, t2);
    EXPECT_EQ(d.steps(), 35u);
}

TEST(StepDetector, TooFewRegularCandidatesAreNotAWalk) {
    StepDetectorConfig c;
    ASSERT_GT(c.bout_steps, 2) << "test assumes the cadence gate is on by default";
    const int n = c.bout_steps - 1;
    StepDetector d(c);
    Walk w;
    walk(d, w, n);
    EXPECT_EQ(d.steps(), 0u);
    // With the gate off the same bumps count.
    c.bout_steps = 1;
    StepDetector off(c);
    walk(off, w, n);
    EXPECT_EQ(off.steps(), static_cast<std::uint64_t>(n));
}

TEST(StepDetector, PlatformStepsCount) {
    StepDetector d;
    const auto e1 = d.push_platform_step(1.0);
    const auto e2 = d.push_platform_step(1.5);
    EXPECT_EQ(d.steps(), 2u);
    EXPECT_DOUBLE_EQ(e1.t_s, 1.0);
    EXPECT_DOUBLE_EQ(e2.t_s, 1.5);
    EXPECT_DOUBLE_EQ(e1.amplitude(), 0.0);  // no accelerometer step seen yet
}

// Phone in a hand swinging like a pendulum from the shoulder: arm angle φ = φ0 sin(ωt) at the
// stride frequency (half the step rate), plus the body's bounce at the step rate and a
// stride-rate vertical sway that makes alternate bumps unequal. The accelerometer reads the hand's
// specific force (kinematic acceleration plus g upwards) in a device frame that turns with the
// arm. Returns the detector's count for `strides` strides (2 steps each).
std::uint64_t swinging_arm(double rate_hz, int strides, double sway, const StepDetectorConfig& c = {}) {
    StepDetector d(c);
    const double L = 0.65, phi0 = 0.6, f_stride = 0.925, bounce = 1.0;
    const double w = 2.0 * kPi * f_stride;
    const double start = 1.5, end_walk = start + strides / f_stride, end = end_walk + 1.5;
    for (double t = 0.0; t < end; t += 1.0 / rate_hz) {
        double phi = 0.0, fx = 0.0, fz = kG;  // world: x forward, z up
        if (t > start && t < end_walk) {
            const double u = w * (t - start);
            phi = phi0 * std::sin(u);
            const double dphi = phi0 * w * std::cos(u), ddphi = -phi0 * w * w * std::sin(u);
            // Hand at L·(sin φ, −cos φ) from the shoulder.
            fx = L * (ddphi * std::cos(phi) - dphi * dphi * std::sin(phi));
            fz += L * (ddphi * std::sin(phi) + dphi * dphi * std::cos(phi));
            fz += bounce * std::cos(2.0 * u) + sway * std::sin(u);
        }
        // Device y along the arm towards the shoulder, x forward across it.
        const double ax = fx * std::cos(phi) + fz * std::sin(phi);
        const double ay = -fx * std::sin(phi) + fz * std::cos(phi);
        d.push(t, ax, ay, 0.0);
    }
    while (d.poll()) {
    }
    return d.steps();
}

// The pendulum's centripetal term L·φ'² peaks twice per swing, so |a| varies at the step rate
// even though the arm swings at the stride rate: the peak detector must count steps, not strides
// (a stride-rate count would be ~50 here). ±2 allows for the abrupt start and end of the swing.
TEST(StepDetector, SwingingArmCountsStepsNotStrides) {
    for (double rate : {50.0, 100.0, 400.0}) {
        for (double sway : {0.0, 1.5}) {
            const auto n = swinging_arm(rate, 50, sway);
            EXPECT_NEAR(static_cast<double>(n), 100.0, 2.0) << rate << " Hz, sway " << sway;
        }
    }
}

// The gravity-aligned vertical signal: the low-passed gravity averages the arm's turning away,
// so the projection also varies at the step rate.
TEST(StepDetector, SwingingArmVerticalSignalAlsoCountsSteps) {
    StepDetectorConfig c;
    c.signal = StepSignal::vertical;
    EXPECT_NEAR(static_cast<double>(swinging_arm(100.0, 50, 1.5, c)), 100.0, 2.0);
}

// Control: the same signal with steps forbidden closer than 0.6 s (between the 0.54 s step and
// the 1.08 s stride) counts one per stride, so the test above does tell steps from strides.
TEST(StepDetector, SwingingArmAtStrideRateWhenStepsAreForbidden) {
    StepDetectorConfig c;
    c.min_step_interval_s = 0.6;
    EXPECT_NEAR(static_cast<double>(swinging_arm(100.0, 50, 1.5, c)), 50.0, 2.0);
}

}  // namespace
}  // namespace pdr_step_detector_test
