// The pieces of real-walk tracking that need no data set: the compass-to-floor rotation and
// mirror learnt from fixes (HeadingAlignment), the corridor axis of a plan, and the walk filter
// following a synthetic walk whose compass is turned and mirrored against the floor.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "locus/motion/fusion/heading_alignment.hpp"
#include "locus/motion/fusion/walk_filter.hpp"
#include "locus/motion/pdr/heading_convention.hpp"

namespace fusion_walk_filter_test {
namespace {

using locus::Point;
namespace fusion = locus::fusion;

constexpr double kPi = std::numbers::pi;

// A rectangle walked clockwise on the floor (30 m × 10 m, 0.7 m steps), as (floor heading, position).
struct Leg {
    double heading;
    int steps;
};
const Leg kLoop[] = {{kPi / 2, 43}, {kPi, 14}, {-kPi / 2, 43}, {0.0, 14}, {kPi / 2, 43}};

// The compass azimuth a phone would give for a floor heading, for a floor turned by `offset`
// and mirrored or not: θ = offset + s·ψ  ⇒  ψ = s·(θ − offset).
double azimuth_of(double floor_heading, double offset, bool mirrored) {
    return locus::pdr::wrap_angle((mirrored ? -1.0 : 1.0) * (floor_heading - offset));
}

TEST(HeadingAlignment, RecoversRotationAndMirrorFromNoisyFixes) {
    for (const bool mirrored : {false, true}) {
        const double offset = 1.1;
        fusion::HeadingAlignment align;
        std::mt19937_64 rng(7);
        std::normal_distribution<double> noise(0.0, 1.5);
        Point at{5, 5};
        int n = 0;
        for (const Leg& leg : kLoop)
            for (int i = 0; i < leg.steps; ++i) {
                at = locus::pdr::step(at, 0.7, leg.heading);
                align.add_step(0.7, azimuth_of(leg.heading, offset, mirrored));
                if (++n % 6 == 0) align.add_fix({at.x + noise(rng), at.y + noise(rng)});
            }
        EXPECT_EQ(align.mirrored(), mirrored);
        EXPECT_NEAR(locus::pdr::wrap_angle(align.offset_rad() - offset), 0.0, 0.15) << "mirrored " << mirrored;
        EXPECT_NEAR(align.scale(), 1.0, 0.2);
        EXPECT_GT(align.correlation(), 0.8);
    }
}

TEST(HeadingAlignment, AssumesNothingBeforeEnoughPairs) {
    fusion::HeadingAlignment align;
    align.add_fix({0, 0});
    align.add_step(0.7, 1.0);
    align.add_fix({0, 0.7});
    EXPECT_EQ(align.offset_rad(), 0.0);
    EXPECT_FALSE(align.mirrored());
    EXPECT_DOUBLE_EQ(align.floor_heading(0.4), 0.4);
}

TEST(CorridorAxis, FindsTheWallsDirection) {
    locus::plan::Plan plan;
    const double a = 0.3;  // walls turned 0.3 rad from the x axis
    for (int i = 0; i < 5; ++i) {
        const Point o{i * 3.0, 0.0};
        plan.walls.push_back({{o, {o.x + 10 * std::cos(a), o.y + 10 * std::sin(a)}}});
        plan.walls.push_back({{o, {o.x - 4 * std::sin(a), o.y + 4 * std::cos(a)}}});  // the perpendicular ones
    }
    const auto axis = fusion::corridor_axis(plan);
    ASSERT_TRUE(axis.has_value());
    EXPECT_NEAR(*axis, a, 0.02);
    EXPECT_FALSE(fusion::corridor_axis(locus::plan::Plan{}).has_value());
}

TEST(WalkFilter, FollowsAWalkWhoseCompassIsTurnedAndMirrored) {
    // No plan: the filter must learn rotation and mirror from the fixes alone.
    fusion::WalkFilterConfig cfg;
    cfg.seed = 3;
    fusion::WalkFilter pf(std::nullopt, cfg);
    EXPECT_FALSE(pf.started());
    std::mt19937_64 rng(11);
    std::normal_distribution<double> noise(0.0, 2.0);
    Point at{5, 5};
    double fix_err = 0.0, pf_err = 0.0;
    int n = 0, scored = 0;
    for (int lap = 0; lap < 2; ++lap)
        for (const Leg& leg : kLoop)
            for (int i = 0; i < leg.steps; ++i) {
                at = locus::pdr::step(at, 0.7, leg.heading);
                pf.step(0.7 / 1.2, azimuth_of(leg.heading, 2.0, true));  // the PDR under-counts length by 1.2×
                if (++n % 6 == 0) {
                    const Point fix{at.x + noise(rng), at.y + noise(rng)};
                    pf.fix(fix, Eigen::Matrix2d::Identity() * 4.0);
                    if (n > 150) {  // after the first lap's learning
                        fix_err += locus::distance(fix, at);
                        pf_err += locus::distance(pf.position(), at);
                        ++scored;
                    }
                }
            }
    ASSERT_GT(scored, 20);
    EXPECT_LT(pf_err / scored, 0.8 * fix_err / scored);
}

// Adaptive re-drawing: a fix the cloud did not expect (20 m off) rebuilds more of the cloud
// round it than the fixed share does, so the estimate lands nearer the fix; a fix where the
// cloud already is changes nothing, whether the share is fixed or adaptive.
TEST(WalkFilter, RedrawsMoreOfTheCloudAroundAFixItDidNotExpect) {
    const Eigen::Matrix2d cov = Eigen::Matrix2d::Identity();
    const auto after = [&](double max_share, Point second_fix) {
        fusion::WalkFilterConfig c;
        c.reseed_fraction = 0.3;
        c.reseed_max_fraction = max_share;
        c.outlier_floor = 0.5;  // the surprising fix must not simply win the resampling
        fusion::WalkFilter f(std::nullopt, c);
        f.fix({0, 0}, cov);
        f.fix(second_fix, cov);
        return f.position();
    };
    const Point far{20, 0};
    const double fixed = std::hypot(after(0.0, far).x - far.x, after(0.0, far).y - far.y);
    const double adaptive = std::hypot(after(0.9, far).x - far.x, after(0.9, far).y - far.y);
    EXPECT_LT(adaptive, fixed - 5.0) << "fixed share " << fixed << " m from the fix, adaptive " << adaptive;
    // k = share·N slots are picked with replacement, so a share of 1 − e^(−share) is re-drawn:
    // 26 % at 0.3, 59 % at 0.9 (surprise ≈ 1); the mean moves that far towards the fix.
    EXPECT_NEAR(fixed, std::exp(-0.3) * 20.0, 1.5);
    EXPECT_NEAR(adaptive, std::exp(-0.9) * 20.0, 1.5);

    const Point expected{0.1, 0.0};
    const Point a = after(0.0, expected), b = after(0.9, expected);
    EXPECT_LT(std::hypot(a.x - expected.x, a.y - expected.y), 1.0);
    EXPECT_LT(std::hypot(b.x - expected.x, b.y - expected.y), 1.0);
}

// The estimate as the cloud's mode: with three quarters of the particles at one place and a
// quarter re-drawn round a fix 20 m away, the mean lies between the two, in neither; the mode
// stays with the larger group.
TEST(WalkFilter, ModeEstimateStaysWithTheLargerGroupWhereTheMeanFallsBetween) {
    const Eigen::Matrix2d cov = Eigen::Matrix2d::Identity();
    const auto after = [&](double radius) {
        fusion::WalkFilterConfig c;
        c.outlier_floor = 0.5;  // the far fix must not simply win the resampling
        c.estimate_radius_m = radius;
        fusion::WalkFilter f(std::nullopt, c);
        f.fix({0, 0}, cov);
        f.fix({20, 0}, cov);
        return f.position();
    };
    const Point mean = after(0.0), mode = after(3.0);
    EXPECT_NEAR(mean.x, (1.0 - std::exp(-0.3)) * 20.0, 1.5);  // 26 % re-drawn (see above)
    EXPECT_LT(std::abs(mode.x), 1.5) << "mode at " << mode.x << ", mean at " << mean.x;
    EXPECT_LT(std::abs(mode.y), 1.0);
}

// KLD-resampling: a cloud in one bin (one place to a centimetre, one rotation) needs no more
// than min_particles; a fixed-size filter (min_particles ≥ particles) keeps them all.
TEST(WalkFilter, ACloudInOneBinShrinksToItsLeastAFixedOneDoesNot) {
    const auto size_after_two_fixes = [](int min_particles) {
        fusion::WalkFilterConfig c;
        c.min_particles = min_particles;
        c.initial_sigma_m = 0.01;
        c.hint_share = 1.0;
        c.hint_sigma_rad = 1e-4;
        c.reseed_fraction = 0.0;
        fusion::WalkFilter f(std::nullopt, c);
        f.hint(0.0, false);
        f.fix({0.5, 0.5}, Eigen::Matrix2d::Identity() * 1e-4);
        EXPECT_EQ(f.size(), 2000u) << "a filter starts with all its particles";
        f.fix({0.5, 0.5}, Eigen::Matrix2d::Identity() * 1e-4);
        return f.size();
    };
    EXPECT_EQ(size_after_two_fixes(150), 150u);
    EXPECT_EQ(size_after_two_fixes(2000), 2000u);
    EXPECT_EQ(size_after_two_fixes(5000), 2000u);
}

// The size follows what the cloud knows: walking the same straight line with the same fixes,
// a cloud told the compass's rotation settles on a few bins (of place; one of rotation) and
// shrinks; one that must learn it from the fixes (fresh particles' rotations drawn uniformly,
// as on a floor without a georeference) keeps half as many again or more.
TEST(WalkFilter, TheCloudKeepsAsManyParticlesAsItsSpreadNeeds) {
    const auto walk = [](bool told) {
        fusion::WalkFilterConfig c;
        c.seed = 9;
        c.min_particles = 100;
        c.kld_epsilon = 0.25;
        c.kld_bin_rad = 0.3;
        c.hint_share = told ? 1.0 : 0.0;
        c.hint_sigma_rad = 0.05;
        c.reseed_fraction = 0.05;
        c.reseed_max_fraction = 0.9;
        fusion::WalkFilter f(std::nullopt, c);
        if (told) f.hint(0.0, false);
        Point at{0, 0};
        f.fix(at, Eigen::Matrix2d::Identity());
        for (int i = 0; i < 12; ++i) {
            for (int s = 0; s < 4; ++s) {
                at = locus::pdr::step(at, 0.7, kPi / 2);
                f.step(0.7, kPi / 2);
            }
            f.fix(at, Eigen::Matrix2d::Identity());
        }
        // Still on the walk: the smaller cloud follows it as well.
        EXPECT_LT(locus::distance(f.position(), at), 1.0) << (told ? "told" : "learning");
        return f.size();
    };
    const std::size_t told = walk(true), learning = walk(false);
    EXPECT_GE(told, 100u);
    EXPECT_LT(told, 1000u);
    EXPECT_GT(2 * learning, 3 * told) << "told " << told << ", learning " << learning;
}

// A floor change through stairs moves the cloud by the stairs' shift and keeps what it learnt:
// the same steps after it walk the same way as a filter that never changed floor, offset by
// the shift (no map on either floor: nothing is re-drawn).
TEST(WalkFilter, ChangingFloorMovesTheCloudAndKeepsWhatItLearnt) {
    fusion::WalkFilterConfig cfg;
    cfg.seed = 5;
    fusion::WalkFilter stays(std::nullopt, cfg);
    stays.fix({5, 5}, Eigen::Matrix2d::Identity());
    for (int i = 0; i < 10; ++i) stays.step(0.7, 0.3);
    fusion::WalkFilter moves = stays;
    const Point shift{-20.0, 3.5};
    moves.change_floor(std::nullopt, shift);
    EXPECT_NEAR(moves.position().x, stays.position().x + shift.x, 1e-4);
    EXPECT_NEAR(moves.position().y, stays.position().y + shift.y, 1e-4);
    EXPECT_NEAR(moves.spread(), stays.spread(), 1e-4);
    for (int i = 0; i < 10; ++i) {
        stays.step(0.7, 0.3);
        moves.step(0.7, 0.3);
    }
    EXPECT_NEAR(moves.position().x, stays.position().x + shift.x, 1e-3);
    EXPECT_NEAR(moves.position().y, stays.position().y + shift.y, 1e-3);
}

}  // namespace
}  // namespace fusion_walk_filter_test
