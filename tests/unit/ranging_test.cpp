// Ranging, the trilateration of the Kalman-fusion paper (docs/spec.md §8) and the
// multilateration on synthetic geometry: without noise both recover the position exactly;
// with shadowing the error stays bounded; the paper's cutoff and too few transmitters answer
// nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "locus/ranging/fit.hpp"
#include "locus/ranging/path_loss.hpp"
#include "locus/ranging/propagation.hpp"
#include "locus/ranging/trilateration.hpp"

namespace ranging_test {
namespace {

using namespace locus;
using namespace locus::ranging;

// The Kalman-fusion paper's layout: anchors around a 20 m × 6 m corridor.
std::vector<Transmitter> corridor() {
    std::vector<Transmitter> out;
    for (double x : {0.0, 5.0, 10.0, 15.0, 20.0})
        for (double y : {0.0, 6.0}) out.push_back({{x, y}, 0.0, {-45.0 - x / 4.0, 2.0 + y / 12.0}});
    return out;
}

std::vector<Heard> heard_at(Point p, const std::vector<Transmitter>& txs, double sigma = 0.0, unsigned seed = 1) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma > 0 ? sigma : 1.0);
    std::vector<Heard> out;
    for (const auto& t : txs) {
        const double d = std::hypot(std::hypot(p.x - t.at.x, p.y - t.at.y), t.dz);
        out.push_back({t, rss_at(t.model, d) + (sigma > 0 ? noise(rng) : 0.0)});
    }
    return out;
}

TEST(PathLoss, RangeInvertsTheModel) {
    const PathLoss m{-40.0, 2.5};
    EXPECT_DOUBLE_EQ(rss_at(m, 1.0), -40.0);
    EXPECT_NEAR(rss_at(m, 10.0), -65.0, 1e-12);
    for (double d : {0.5, 1.0, 3.7, 25.0}) EXPECT_NEAR(range_of(m, rss_at(m, d)), d, 1e-9 * d);
    EXPECT_NEAR(horizontal(5.0, 3.0), 4.0, 1e-12);
    EXPECT_EQ(horizontal(2.0, 3.0), 0.0);
}

TEST(Trilateration, ExactWithoutNoise) {
    const auto txs = corridor();
    for (Point p : {Point{2.0, 3.0}, Point{7.5, 1.0}, Point{12.0, 4.5}, Point{18.0, 2.0}}) {
        const auto heard = heard_at(p, txs);
        const auto fix = trilaterate(heard);
        ASSERT_TRUE(fix) << p.x << "," << p.y;
        EXPECT_NEAR(fix->at.x, p.x, 1e-6);
        EXPECT_NEAR(fix->at.y, p.y, 1e-6);
        EXPECT_GE(fix->used, 3);
        // The paper's 10 m cutoff leaves the far anchors out.
        EXPECT_LT(fix->used, static_cast<int>(txs.size()));
    }
}

TEST(Trilateration, CutoffAndTooFewAnswerNothing) {
    const auto txs = corridor();
    const auto heard = heard_at({2.0, 3.0}, txs);
    TrilaterationOptions tight;
    tight.cutoff = 3.0;  // only the two anchors at x = 0 are within 3 m... and (5, 0)? 3.6 m: no
    EXPECT_FALSE(trilaterate(heard, tight));
    EXPECT_FALSE(trilaterate(std::span(heard).first(2)));
}

TEST(Trilateration, VotingRepairsOneBadRange) {
    const auto txs = corridor();
    const Point p{5.0, 1.0};
    auto heard = heard_at(p, txs);
    // The anchor at (0, 0), 5.1 m away, reads as if 9.5 m away (a body in the way): within the
    // cutoff, but past what the reference (5, 0), 1 m away and 5 m from it, allows (6 m).
    ASSERT_EQ(txs[0].at.x, 0.0);
    ASSERT_EQ(txs[0].at.y, 0.0);
    heard[0].rss = rss_at(txs[0].model, 9.5);
    TrilaterationOptions plain;
    plain.correct = false;
    const auto raw = trilaterate(heard, plain);
    const auto voted = trilaterate(heard);
    ASSERT_TRUE(raw && voted);
    EXPECT_LT(distance(voted->at, p), distance(raw->at, p));
}

TEST(Multilateration, ExactWithoutNoiseAndWithHeights) {
    auto txs = corridor();
    for (auto& t : txs) t.dz = 2.0;  // on the ceiling, 2 m above the phone
    for (Point p : {Point{2.0, 3.0}, Point{7.5, 1.0}, Point{12.0, 4.5}, Point{18.0, 2.0}, Point{10.0, 3.0}}) {
        const auto fix = multilaterate(heard_at(p, txs));
        ASSERT_TRUE(fix);
        EXPECT_NEAR(fix->at.x, p.x, 1e-3) << p.x << "," << p.y;
        EXPECT_NEAR(fix->at.y, p.y, 1e-3) << p.x << "," << p.y;
        EXPECT_EQ(fix->used, static_cast<int>(txs.size()));
        EXPECT_LT(fix->rms_residual, 1e-3);
        EXPECT_GT(fix->uncertainty.semi_major, 0.0);
        EXPECT_GE(fix->uncertainty.semi_major, fix->uncertainty.semi_minor);
    }
}

TEST(Multilateration, NoiseGivesBoundedErrorAndBeatsTrilateration) {
    const auto txs = corridor();
    double multi = 0, tri = 0;
    int n = 0, inside_ellipse = 0;
    for (unsigned seed = 1; seed <= 200; ++seed) {
        const Point p{1.0 + (seed * 37 % 180) / 10.0, 0.5 + (seed * 11 % 50) / 10.0};
        const auto heard = heard_at(p, txs, 3.0, seed);
        const auto m = multilaterate(heard);
        const auto t = trilaterate(heard);
        ASSERT_TRUE(m);
        const double e = distance(m->at, p);
        multi += e;
        if (e <= 2.5 * m->uncertainty.semi_major) ++inside_ellipse;
        tri += t ? distance(t->at, p) : 10.0;
        ++n;
    }
    multi /= n;
    tri /= n;
    EXPECT_LT(multi, 2.0) << "mean error of multilateration with 3 dB shadowing";
    EXPECT_LT(multi, tri);
    // The ellipse is a real uncertainty: most errors lie within 2.5 semi-major axes.
    EXPECT_GT(inside_ellipse, n * 8 / 10);
}

TEST(Multilateration, RobustToOneWildReading) {
    const auto txs = corridor();
    const Point p{9.0, 2.0};
    auto heard = heard_at(p, txs, 1.0, 7);
    heard[0].rss = -20.0;  // a glitch: 0 m from an anchor 9 m away
    const auto fix = multilaterate(heard);
    ASSERT_TRUE(fix);
    EXPECT_LT(distance(fix->at, p), 1.5);
}

TEST(Multilateration, TooFewIsNothing) {
    const auto heard = heard_at({1, 1}, corridor());
    EXPECT_FALSE(multilaterate(std::span(heard).first(2)));
}

TEST(Ellipse, AxesAndAngleOfACovariance) {
    const auto e = ellipse_of(4.0, 1.0, 0.0);
    EXPECT_DOUBLE_EQ(e.semi_major, 2.0);
    EXPECT_DOUBLE_EQ(e.semi_minor, 1.0);
    EXPECT_DOUBLE_EQ(e.angle_deg, 0.0);
    const auto turned = ellipse_of(2.5, 2.5, 1.5);  // axes along ±45°
    EXPECT_NEAR(turned.angle_deg, 45.0, 1e-9);
    EXPECT_NEAR(turned.semi_major, 2.0, 1e-9);
    EXPECT_NEAR(turned.semi_minor, 1.0, 1e-9);
}

std::vector<Sample> survey_of(const Transmitter& t, double sigma, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma > 0 ? sigma : 1.0);
    std::vector<Sample> out;
    for (double x = 1; x < 30; x += 2.5)
        for (double y = 1; y < 20; y += 2.5) {
            const double d = std::hypot(std::hypot(x - t.at.x, y - t.at.y), t.dz);
            out.push_back({{x, y}, rss_at(t.model, d) + (sigma > 0 ? noise(rng) : 0.0)});
        }
    return out;
}

TEST(Fit, ModelAtAKnownPositionIsExactWithoutNoise) {
    const Transmitter t{{12.0, 7.0}, 1.5, {-43.0, 2.7}};
    const auto s = survey_of(t, 0.0, 1);
    const auto f = fit_model(s, t.at, t.dz);
    ASSERT_TRUE(f);
    EXPECT_NEAR(f->model.tx_power, -43.0, 1e-9);
    EXPECT_NEAR(f->model.exponent, 2.7, 1e-9);
    EXPECT_NEAR(f->r2, 1.0, 1e-12);
    EXPECT_NEAR(f->residual_db, 0.0, 1e-9);
}

TEST(Fit, PositionAndModelFromANoisySurvey) {
    const Transmitter t{{21.3, 4.2}, 0.0, {-38.0, 2.3}};
    const auto s = survey_of(t, 2.0, 3);
    FitOptions o;
    o.area = {0, 0, 30, 20};
    const auto f = fit_position_and_model(s, o);
    ASSERT_TRUE(f);
    EXPECT_LT(distance(f->at, t.at), 1.0);
    EXPECT_NEAR(f->model.tx_power, -38.0, 2.0);
    EXPECT_NEAR(f->model.exponent, 2.3, 0.3);
    EXPECT_GT(f->r2, 0.8);
    EXPECT_NEAR(f->residual_db, 2.0, 0.5);
}

TEST(Fit, TooFewOrDegenerateSamplesAreNothing) {
    const Transmitter t{{5.0, 5.0}, 0.0, {-40.0, 2.0}};
    const auto s = survey_of(t, 0.0, 1);
    EXPECT_FALSE(fit_model(std::span(s).first(2), t.at, 0.0));
    EXPECT_FALSE(fit_position_and_model(std::span(s).first(3), {}));
    const std::vector<Sample> ring{{{6, 5}, -40}, {{4, 5}, -41}, {{5, 6}, -42}};  // all 1 m away
    EXPECT_FALSE(fit_model(ring, t.at, 0.0));
}

TEST(Propagation, WallsCrossedMatchABruteForceCount) {
    std::vector<Segment> walls;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 40.0), len(0.5, 6.0);
    for (int i = 0; i < 300; ++i) {
        const Point a{u(rng), u(rng)};
        walls.push_back(i % 2 ? Segment{a, {a.x + len(rng), a.y}} : Segment{a, {a.x, a.y + len(rng)}});
    }
    walls.push_back({{10, 0}, {10, 40}});  // on a cell boundary (cells of 2 m)
    const WallIndex index(walls, 2.0);
    for (int q = 0; q < 500; ++q) {
        const Point a{u(rng), u(rng)};
        const Point b = q % 10 == 0 ? Point{a.x, u(rng)} : Point{u(rng), u(rng)};  // some vertical paths
        int brute = 0;
        for (const auto& w : walls) brute += segments_intersect(a, b, w.a, w.b) ? 1 : 0;
        ASSERT_EQ(index.crossed(a, b), brute) << a.x << "," << a.y << " -> " << b.x << "," << b.y;
    }
}

TEST(Propagation, EachWallCostsItsAttenuation) {
    const std::vector<ModelledTransmitter> txs{{{{0.0, 0.0}, 0.0, {-40.0, 2.0}}, 5.0}, {{{0.0, 0.0}, 0.0, {-40.0, 2.0}}, std::nullopt}};
    const WallIndex walls({{{3, -5}, {3, 5}}, {{6, -5}, {6, 5}}});
    const auto r = modelled_rss({10.0, 0.0}, txs, walls, -100.0);
    ASSERT_EQ(r.size(), 2u);
    EXPECT_NEAR(r[0].rss, -60.0 - 10.0, 1e-9);  // two walls of 5 dB
    EXPECT_NEAR(r[1].rss, -60.0, 1e-9);         // walls not modelled
    EXPECT_TRUE(modelled_rss({10.0, 0.0}, txs, walls, -65.0).size() == 1);  // below the floor: left out
    EXPECT_EQ(grid_points({0, 0, 10, 4}, 2.0).size(), 10u);
}

}  // namespace
}  // namespace ranging_test
