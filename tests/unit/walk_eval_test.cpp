// `locus eval walks`' evaluation (tools/walk_eval): causality — cutting a walk after scan i
// (its accelerometer, orientation and scans, and the fixes) leaves every causal method's
// estimate at scan i unchanged — and the figures it reports. On the tiny PUTMC fixture and,
// when the shared data folder is there, on a whole real walk.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "putmc_thin.hpp"
#include "walk_eval.hpp"
#include "walk_reality.hpp"
#include "build_paths.hpp"

namespace walk_eval_test {
namespace {

namespace putmc = locus::datasets::putmc;
namespace walks = locus::tools::walks;
using locus::Point;

constexpr double kHeight = 36.938098400633;  // the PUTMC floor's, as import putmc makes it

// Fixes near the truth, off by a fixed pattern (no server here; the HTTP path has its own test).
std::vector<std::optional<locus::sim::Fix>> fixes_of(const putmc::Walk& w) {
    std::vector<std::optional<locus::sim::Fix>> out;
    for (std::size_t i = 0; i < w.scans.size(); ++i) {
        const Point t = putmc::to_floor(w.truth_of(w.scans[i]), kHeight);
        locus::sim::Fix f;
        f.t_s = w.scans[i].t_s;
        f.at = {t.x + 2.0 * std::sin(1.7 * i), t.y + 1.5 * std::cos(2.3 * i)};
        f.aps = 20;
        f.cov = Eigen::Matrix2d::Identity() * 4.0;
        out.push_back(i % 5 == 3 ? std::nullopt : std::optional(f));  // every fifth scan matched nothing
    }
    return out;
}

putmc::Walk cut_after(const putmc::Walk& w, std::size_t scan) {
    putmc::Walk c = w;
    const double t = w.scans[scan].t_s;
    std::erase_if(c.acc, [&](const putmc::AccSample& s) { return s.t_s > t; });
    std::erase_if(c.orient, [&](const putmc::OrientSample& s) { return s.t_s > t; });
    c.scans.resize(scan + 1);
    return c;
}

// One open hall over the whole floor, walled round, so the particle filters have a plan.
locus::fusion::Walkable hall() {
    locus::plan::Plan plan;
    locus::plan::Space s;
    s.name = "hall";
    s.shape.outer = {{0, 0}, {108, 0}, {108, kHeight}, {0, kHeight}};
    plan.spaces.push_back(s);
    plan.walls.push_back({{{0, 0}, {108, 0}, {108, kHeight}, {0, kHeight}, {0, 0}}});
    return locus::fusion::Walkable::from_plan(plan);
}

void expect_causal(const putmc::Walk& walk) {
    const auto fixes = fixes_of(walk);
    const std::optional<locus::fusion::Walkable> map = hall();
    walks::Config cfg;
    cfg.walk_filter.particles = 300;
    cfg.methods.particle.particles = 300;
    const auto full = walks::evaluate_walk(walk, fixes, kHeight, map, cfg);
    ASSERT_GT(full.steps, 0u);
    for (std::size_t i = 0; i < walk.scans.size(); i += std::max<std::size_t>(1, walk.scans.size() / 4)) {
        const auto cut = cut_after(walk, i);
        const std::vector<std::optional<locus::sim::Fix>> cut_fixes(fixes.begin(), fixes.begin() + i + 1);
        const auto part = walks::evaluate_walk(cut, cut_fixes, kHeight, map, cfg);
        ASSERT_EQ(part.tracks.size(), full.tracks.size());
        for (std::size_t m = 0; m < full.tracks.size(); ++m) {
            const auto& a = full.tracks[m].at_scan[i];
            const auto& b = part.tracks[m].at_scan[i];
            ASSERT_EQ(a.has_value(), b.has_value()) << full.tracks[m].method << " at scan " << i;
            if (a) {
                EXPECT_EQ(a->x, b->x) << full.tracks[m].method << " at scan " << i;
                EXPECT_EQ(a->y, b->y) << full.tracks[m].method << " at scan " << i;
            }
        }
    }
}

TEST(WalkEval, CuttingTheWalkLeavesEarlierEstimatesUnchangedOnTheFixture) {
    expect_causal(putmc::read_walk(std::string(LOCUS_TEST_FIXTURES) + "/putmc/trajs/tiny_walk"));
}

TEST(WalkEval, CuttingTheWalkLeavesEarlierEstimatesUnchangedOnARealWalk) {
    const std::string dir = std::string(LOCUS_DATA_DIR) + "/putmc/trajs/xperia_traj5";
    if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " not found: the shared data folder is absent";
    expect_causal(putmc::read_walk(dir));
}

TEST(WalkEval, ScoresEveryScanAndWifiIsTheFixHeld) {
    const auto walk = putmc::read_walk(std::string(LOCUS_TEST_FIXTURES) + "/putmc/trajs/tiny_walk");
    const auto fixes = fixes_of(walk);
    const auto r = walks::evaluate_walk(walk, fixes, kHeight, std::nullopt, walks::Config{});
    EXPECT_EQ(r.truth.size(), 3u);
    EXPECT_EQ(r.fixes, 3u);
    const auto wifi = walks::errors_of(r, "wifi");
    ASSERT_EQ(wifi.size(), 3u);
    EXPECT_NEAR(wifi[0], std::hypot(2.0 * std::sin(0.0), 1.5 * std::cos(0.0)), 1e-9);
    EXPECT_NEAR(wifi[1], std::hypot(2.0 * std::sin(1.7), 1.5 * std::cos(2.3)), 1e-9);
    // No particle filter without a plan, but the walk filter runs free (walk_pf_local: walk_pf
    // itself is the server's live track, which eval walks posts to).
    EXPECT_TRUE(walks::errors_of(r, "particle").empty());
    EXPECT_EQ(walks::errors_of(r, "walk_pf_local").size(), 3u);
    EXPECT_TRUE(walks::errors_of(r, "walk_pf").empty());
    const auto s = walks::stats_of({1.0, 2.0, 3.0, 4.0});
    EXPECT_DOUBLE_EQ(s.mean, 2.5);
    EXPECT_DOUBLE_EQ(s.median, 2.5);
    EXPECT_DOUBLE_EQ(s.p75, 3.25);
}

TEST(WalkEval, AWalkWithNoFixHasNoEstimate) {
    const auto walk = putmc::read_walk(std::string(LOCUS_TEST_FIXTURES) + "/putmc/trajs/tiny_walk");
    const std::vector<std::optional<locus::sim::Fix>> none(walk.scans.size());
    const auto r = walks::evaluate_walk(walk, none, kHeight, std::nullopt, walks::Config{});
    EXPECT_EQ(r.fixes, 0u);
    for (const auto& t : r.tracks) EXPECT_TRUE(walks::errors_of(r, t.method).empty()) << t.method;
}

TEST(WalkEval, SmoothersUseTheFutureAndAreLabelledSo) {
    // The offline smoothers are the only methods not causal: cutting the walk moves their
    // estimate at an earlier scan. The tuned rules are causal (expect_causal covers them).
    const auto walk = putmc::read_walk(std::string(LOCUS_TEST_FIXTURES) + "/putmc/trajs/tiny_walk");
    const auto fixes = fixes_of(walk);
    walks::Config cfg;
    cfg.smooth = true;
    cfg.walk_filter.particles = 300;
    cfg.methods.particle.particles = 300;
    const std::optional<locus::fusion::Walkable> map = hall();
    const auto full = walks::evaluate_walk(walk, fixes, kHeight, map, cfg);
    const auto part = walks::evaluate_walk(cut_after(walk, 0), {fixes.begin(), fixes.begin() + 1}, kHeight, map, cfg);
    for (const char* m : {"rts_smoother", "pf_smoother"}) {
        const auto pick = [&](const walks::WalkResult& r) {
            for (const auto& t : r.tracks)
                if (t.method == m) return t.at_scan[0];
            return std::optional<Point>();
        };
        ASSERT_TRUE(pick(full) && pick(part)) << m;
        EXPECT_GT(locus::distance(*pick(full), *pick(part)), 1e-6) << m << " did not use the rest of the walk";
    }
    for (const auto& name : walks::method_names(true, true)) {
        if (name == "walk_pf") continue;  // the server's live track: `locus eval walks` posts it, not evaluate_walk
        EXPECT_TRUE(std::any_of(full.tracks.begin(), full.tracks.end(), [&](const walks::MethodTrack& t) { return t.method == name; }))
            << name;
    }
}

TEST(WalkReality, ErrorCorrelationIsOneForASharedErrorAndMinusOneForOpposite) {
    // Fixes 3 m apart: the same error vector (a field fixed per place) and the opposite one.
    walks::RealityStats same, opposite;
    same.fix_truth = opposite.fix_truth = {{0.0, 0.0}, {3.0, 0.0}, {20.0, 0.0}};
    same.fix_error = {{1.0, 2.0}, {1.0, 2.0}, {0.0, 0.0}};
    opposite.fix_error = {{1.0, 2.0}, {-1.0, -2.0}, {0.0, 0.0}};
    const auto a = walks::error_correlation({same}, {0.0, 4.0, 30.0});
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a[0].pairs, 1u);
    EXPECT_NEAR(a[0].correlation, 1.0, 1e-12);
    EXPECT_EQ(a[1].pairs, 2u);
    EXPECT_NEAR(walks::error_correlation({opposite}, {0.0, 4.0})[0].correlation, -1.0, 1e-12);
    // Pairs are taken within a walk only.
    walks::RealityStats first = same, second = same;
    first.fix_truth.resize(1), first.fix_error.resize(1), second.fix_truth.resize(1), second.fix_error.resize(1);
    EXPECT_EQ(walks::error_correlation({first, second}, {0.0, 4.0})[0].pairs, 0u);
}

// A thin client's batches (tools/putmc_thin): one per scan, every step the detector confirmed
// up to the last scan in exactly one batch, each after the previous scan and by its own.
TEST(ThinBatches, EveryStepUpToTheLastScanInTheBatchOfItsScan) {
    const std::string dir = std::string(LOCUS_DATA_DIR) + "/putmc/trajs/xperia_traj1";
    if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " not found: the shared data folder is absent";
    const auto walk = putmc::read_walk(dir);
    const auto batches = walks::thin_batches(walk);
    ASSERT_EQ(batches.size(), walk.scans.size());
    const auto all = walks::detect_steps(walk, walk.scans.back().t_s);
    std::size_t seen = 0;
    double previous = -INFINITY;
    for (std::size_t i = 0; i < batches.size(); ++i) {
        EXPECT_EQ(batches[i].scan, &walk.scans[i]);
        EXPECT_EQ(batches[i].t_s, walk.scans[i].t_s);
        EXPECT_EQ(batches[i].truth.x, walk.truth_of(walk.scans[i]).x);
        for (const auto& s : batches[i].steps) {
            EXPECT_GT(s.t_s, previous);
            EXPECT_LE(s.t_s, batches[i].t_s);
            ASSERT_LT(seen, all.size());
            EXPECT_EQ(s.t_s, all[seen].t_s);
            ++seen;
        }
        previous = batches[i].t_s;
    }
    EXPECT_EQ(seen, all.size());
    EXPECT_GT(seen, 100u);  // a real walk of a few minutes
}

}  // namespace
}  // namespace walk_eval_test
