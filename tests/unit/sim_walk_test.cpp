// The walking simulator: scenarios as Traini 2017 describes them, determinism, physically
// sensible sensors, walk files that round-trip, and the real PDR counting its steps.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "locus/motion/pdr/heading_convention.hpp"
#include "sim/environment.hpp"
#include "sim/evaluate.hpp"
#include "sim/generator.hpp"
#include "sim/scenario.hpp"
#include "sim/walk_io.hpp"

namespace sim_walk_test {
namespace {

using namespace locus;
using namespace locus::sim;

TEST(SimScenario, FloorsHaveTheSeedAreasAndWalks) {
    EXPECT_NEAR(scenario("ground").area_m2(), 222.8, 1e-9);
    EXPECT_NEAR(scenario("basement").area_m2(), 452.4, 1e-9);
    EXPECT_NEAR(scenario("basement").path_length_m(), 52.0, 1e-9);  // Traini 2017 §4.3.3
    EXPECT_NEAR(scenario("ground").path_length_m(), 26.5, 1e-9);    // Traini 2017: "26 m"
    EXPECT_THROW(scenario("attic"), std::invalid_argument);
}

TEST(SimScenario, PathsGoThroughDoorsAndRpsLieOnThem) {
    for (const std::string& name : scenario_names()) {
        const Scenario& sc = scenario(name);
        // Walk the path in 10 cm moves: every move must be legal on the plan.
        const double total = sc.path_length_m();
        Point last = sc.path.front();
        for (double s = 0.1; s <= total; s += 0.1) {
            const Point p = point_at_arc(sc.path, s);
            ASSERT_TRUE(sc.map.can_move(last, p)) << name << " at arc " << s;
            last = p;
        }
        ASSERT_GE(sc.rps.size(), 10u);
        for (const Point& rp : sc.rps) EXPECT_TRUE(sc.map.inside(rp));
        EXPECT_NEAR(distance(sc.rps.front(), sc.path.front()), 0.0, 1e-9);
        EXPECT_NEAR(distance(sc.rps.back(), sc.path.back()), 0.0, 1e-9);
    }
}

TEST(SimEnvironment, PathLossAndTheBasementAnomaly) {
    const Scenario& sc = scenario("basement");
    const Environment env(sc);
    // Same room, no walls: farther is weaker (shadowing is a few dB, 1 m vs 8 m is ~22 dB).
    const Point ap = sc.aps[0].at;
    EXPECT_GT(env.mean_rss(0, {ap.x - 1.0, ap.y}), env.mean_rss(0, {ap.x - 8.0, ap.y - 1.0}) + 10.0);
    // The technical room's source: |B| near it is far from Earth's, far away it is not.
    const double earth = std::hypot(sc.earth_horizontal_ut, sc.earth_vertical_ut);
    const Point near_source{sc.sources[0].at.x + 1.0, sc.sources[0].at.y};
    EXPECT_GT(std::abs(env.magnetic_field(near_source).norm() - earth), 0.3 * earth);
    EXPECT_LT(std::abs(env.magnetic_field({30.0, 12.0}).norm() - earth), 0.2 * earth);
}

TEST(SimWalk, SameSeedSameWalkOtherSeedOtherWalk) {
    const Walk a = simulate(scenario("ground"), 7);
    const Walk b = simulate(scenario("ground"), 7);
    const Walk c = simulate(scenario("ground"), 8);
    ASSERT_EQ(a.imu.size(), b.imu.size());
    for (std::size_t i = 0; i < a.imu.size(); i += 97) {
        EXPECT_EQ(a.imu[i].acc.z, b.imu[i].acc.z);
        EXPECT_EQ(a.imu[i].mag.x, b.imu[i].mag.x);
    }
    ASSERT_EQ(a.scans.size(), b.scans.size());
    EXPECT_EQ(a.scans[2].readings.size(), b.scans[2].readings.size());
    EXPECT_NE(a.imu[200].acc.z, c.imu[200].acc.z);
}

TEST(SimWalk, SensorsAreSensible) {
    const Walk w = simulate(scenario("ground"), 3);
    EXPECT_NEAR(w.imu[1].t_s - w.imu[0].t_s, 0.02, 1e-12);  // 50 Hz
    // Standing still at the start: the accelerometer reads g (plus bias and noise).
    const auto& a = w.imu[10].acc;
    EXPECT_NEAR(std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z), 9.81, 0.4);
    // Truth starts at the path start and ends at its end.
    EXPECT_NEAR(distance(*w.imu.front().truth, scenario("ground").path.front()), 0.0, 1e-9);
    EXPECT_NEAR(distance(*w.imu.back().truth, scenario("ground").path.back()), 0.0, 1e-9);
    // Scans every 3 s, each hearing some but not all of the 8 APs.
    ASSERT_GE(w.scans.size(), 6u);
    for (const WifiScan& s : w.scans) {
        EXPECT_GE(s.readings.size(), 2u);
        for (const Reading& r : s.readings) EXPECT_TRUE(valid_rss(r.rss));
    }
    EXPECT_EQ(w.survey.size(), scenario("ground").rps.size());
    EXPECT_EQ(w.survey[0].scans.size(), 30u);
}

TEST(SimWalk, RealPdrCountsTheStepsAndWalksTheDistance) {
    // A person of the nominal 0.70 m step: the default spread of people's step lengths
    // (±15 %, Traini 2017's PDR distance errors) would make the step count unknown here.
    SimConfig cfg;
    cfg.step_length_person_sigma = 0.0;
    const Walk w = simulate(scenario("ground"), 5, cfg);
    const std::vector<PdrStep> steps = run_pdr(w);
    double walked = 0.0;
    for (const PdrStep& s : steps) walked += s.length_m;
    // 26.5 m at ~0.7 m per step is ~38 steps; the person's bounce makes Weinberg off by
    // a few %.
    EXPECT_NEAR(static_cast<double>(steps.size()), 26.5 / 0.7, 5.0);
    EXPECT_NEAR(walked, 26.5, 0.2 * 26.5);
}

TEST(SimWalk, FileRoundTrip) {
    const Walk w = simulate(scenario("basement"), 2);
    std::stringstream buf;
    write_walk(buf, w);
    const Walk r = read_walk(buf);
    EXPECT_EQ(r.scenario, "basement");
    EXPECT_EQ(r.seed, 2u);
    ASSERT_EQ(r.imu.size(), w.imu.size());
    ASSERT_EQ(r.scans.size(), w.scans.size());
    ASSERT_EQ(r.survey.size(), w.survey.size());
    EXPECT_EQ(r.imu[123].gyro.y, w.imu[123].gyro.y);
    EXPECT_EQ(r.imu[123].truth->x, w.imu[123].truth->x);
    EXPECT_EQ(r.scans[3].readings.size(), w.scans[3].readings.size());
    EXPECT_EQ(r.survey[4].scans[7].size(), w.survey[4].scans[7].size());
    ASSERT_TRUE(r.map.has_value());
    EXPECT_EQ(r.map->doors.size(), w.map->doors.size());
    EXPECT_EQ(r.earth_field_ut, w.earth_field_ut);
    // The evaluation of the re-read walk is the evaluation of the walk.
    EXPECT_EQ(evaluate(r)[0].mean_error_m, evaluate(w)[0].mean_error_m);

    std::stringstream bad("{\"type\":\"imu\",\"t\":0}\n");
    EXPECT_THROW(read_walk(bad), std::runtime_error);
}

TEST(SimWalk, TruthIsInterpolatedBetweenSamples) {
    Walk w;
    w.imu.resize(2);
    w.imu[0].t_s = 0.0;
    w.imu[0].truth = Point{0.0, 0.0};
    w.imu[1].t_s = 0.02;
    w.imu[1].truth = Point{1.0, 2.0};
    EXPECT_NEAR(w.truth_at(0.005)->x, 0.25, 1e-12);
    EXPECT_NEAR(w.truth_at(0.005)->y, 0.5, 1e-12);
    EXPECT_EQ(w.truth_at(5.0)->x, 1.0);
}

TEST(SimEvaluate, EveryMethodInTheIssueOrderAndPdrOnlyDriftsInTheBasement) {
    const std::vector<Score> s = evaluate(simulate(scenario("basement"), 4));
    const std::vector<std::string> expected{"pdr",           "wifi",   "only_wifi", "midpoint", "midpoint_threshold",
                                            "proportional",  "proportional2", "kalman", "particle"};
    ASSERT_EQ(s.size(), expected.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        EXPECT_EQ(s[i].method, expected[i]);
        EXPECT_GT(s[i].points, 5u);
        EXPECT_LE(s[i].mean_error_m, s[i].p95_error_m + 1e-9);
    }
    // The disturbed compass sends PDR alone metres off; any fusion with WiFi pulls it back.
    for (std::size_t i = 2; i < s.size(); ++i) EXPECT_LT(s[i].mean_error_m, s[0].mean_error_m) << s[i].method;
}

bool same_scan(const Scan& a, const Scan& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].bssid != b[i].bssid || a[i].rss != b[i].rss) return false;
    return true;
}

TEST(SimWalk, SurveyDriftAndScanSweepChangeOnlyTheOnlineScans) {
    SimConfig still;
    still.survey_drift_sigma_db = 0.0;
    still.scan_duration_s = 0.0;
    const Walk a = simulate(scenario("basement"), 9);
    const Walk b = simulate(scenario("basement"), 9, still);
    // The radio map (survey) and the person are the same walk...
    ASSERT_EQ(a.survey.size(), b.survey.size());
    for (std::size_t i = 0; i < a.survey.size(); ++i) EXPECT_TRUE(same_scan(a.survey[i].scans[5], b.survey[i].scans[5]));
    ASSERT_EQ(a.imu.size(), b.imu.size());
    EXPECT_EQ(a.imu[321].acc.z, b.imu[321].acc.z);
    EXPECT_EQ(a.imu[321].mag.x, b.imu[321].mag.x);
    // ...but what the phone hears online is not what the survey heard there.
    ASSERT_EQ(a.scans.size(), b.scans.size());
    int differing = 0;
    for (std::size_t i = 0; i < a.scans.size(); ++i) differing += !same_scan(a.scans[i].readings, b.scans[i].readings);
    EXPECT_GT(differing, static_cast<int>(a.scans.size()) / 2);
}

TEST(SimEvaluate, FiltersCanMoveALateFixByTheStepsTakenSince) {
    // Three 1 m steps north at t = 1, 2, 3 s; a near-certain fix at (0, 5) arrives at 3.5 s.
    // With a 1 s latency the fix stands for 2.5 s, so the step at 3 s is added: (0, 6).
    const std::vector<PdrStep> steps{{1.0, 1.0, 0.0, false}, {2.0, 1.0, 0.0, false}, {3.0, 1.0, 0.0, false}};
    Fix fix;
    fix.t_s = 3.5;
    fix.at = {0.0, 5.0};
    fix.aps = 5;
    fix.cov = 1e-8 * Eigen::Matrix2d::Identity();
    auto kalman_end = [&](double latency) {
        EvalConfig cfg;
        cfg.kalman_fix_latency_s = latency;
        for (const NamedTrack& t : run_methods(steps, {fix}, {0.0, 0.0}, std::nullopt, cfg))
            if (t.method == "kalman") return t.track.back().at;
        return Point{-1.0, -1.0};
    };
    EXPECT_NEAR(kalman_end(0.0).y, 5.0, 1e-4);
    EXPECT_NEAR(kalman_end(1.0).y, 6.0, 1e-4);
    EXPECT_NEAR(kalman_end(1.0).x, 0.0, 1e-4);
    // 2.6 s back: every step after 0.9 s, all three.
    EXPECT_NEAR(kalman_end(2.6).y, 8.0, 1e-4);
    // The rules never move the fix: only_wifi answers it as it came.
    EvalConfig cfg;
    cfg.kalman_fix_latency_s = 1.0;
    cfg.particle_fix_latency_s = 1.0;
    for (const NamedTrack& t : run_methods(steps, {fix}, {0.0, 0.0}, std::nullopt, cfg)) {
        if (t.method == "only_wifi") {
            EXPECT_NEAR(t.track.back().at.y, 5.0, 1e-12);
        }
    }
}

TEST(SimWalk, HeadingWalkTurnsOnlyTheCompassAndSendsPdrFurtherOff) {
    SimConfig fixed;
    fixed.heading_walk_rad_per_sqrt_m = 0.0;
    double pdr_wander = 0.0, pdr_fixed = 0.0;
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
        const Walk a = simulate(scenario("ground"), seed);
        const Walk b = simulate(scenario("ground"), seed, fixed);
        // The same person on the same path hearing the same radio...
        ASSERT_EQ(a.imu.size(), b.imu.size());
        EXPECT_EQ(a.imu.back().truth->x, b.imu.back().truth->x);
        ASSERT_EQ(a.scans.size(), b.scans.size());
        for (std::size_t i = 0; i < a.scans.size(); ++i) EXPECT_TRUE(same_scan(a.scans[i].readings, b.scans[i].readings));
        // ...with the compass the same while standing at the start and turned later on.
        EXPECT_EQ(a.imu[10].mag.x, b.imu[10].mag.x);
        EXPECT_NE(a.imu[a.imu.size() - 10].mag.x, b.imu[b.imu.size() - 10].mag.x);
        pdr_wander += evaluate(a)[0].final_error_m;
        pdr_fixed += evaluate(b)[0].final_error_m;
    }
    // 0.28 rad/√m over 26.5 m is ~1.4 rad at the end: PDR alone ends much further off.
    EXPECT_GT(pdr_wander, 1.5 * pdr_fixed);
}

}  // namespace
}  // namespace sim_walk_test
