// The Kalman-fusion paper's setting (docs/spec.md §8) in the simulator: anchors at known positions
// heard once a second on the open_area scenario only, their readings following the log-distance
// model, walk files carrying them, and the ranging methods' filters: each Kalman filter must beat
// both of its inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>

#include "locus/motion/pdr/heading_convention.hpp"
#include "sim/environment.hpp"
#include "sim/generator.hpp"
#include "sim/ranging_eval.hpp"
#include "sim/scenario.hpp"
#include "sim/walk_io.hpp"

namespace sim_anchors_test {
namespace {

using namespace locus;
using namespace locus::sim;

TEST(SimAnchors, OnlyOpenAreaHasAnchorsAndTheyAreHeardOnceASecond) {
    const Walk ground = simulate(scenario("ground"), 7);
    EXPECT_TRUE(ground.anchors.empty());
    EXPECT_TRUE(ground.anchor_scans.empty());

    const Scenario& sc = scenario("open_area");
    EXPECT_NEAR(sc.area_m2(), 300.0, 1e-9);  // the Kalman-fusion paper §4: a 300 m² area
    int ble = 0, wifi = 0;
    for (const Beacon& b : sc.beacons) (b.type == "ble" ? ble : wifi) += 1;
    EXPECT_EQ(ble, 4);  // 4 Sensor Tags and 2 Aironets
    EXPECT_EQ(wifi, 2);
    const Walk w = simulate(sc, 7, default_config("open_area"));
    ASSERT_EQ(w.anchors.size(), sc.beacons.size());
    const double duration = w.imu.back().t_s;
    EXPECT_NEAR(static_cast<double>(w.anchor_scans.size()), duration, 1.0);
    for (std::size_t i = 1; i < w.anchor_scans.size(); ++i)
        EXPECT_NEAR(w.anchor_scans[i].t_s - w.anchor_scans[i - 1].t_s, 1.0, 1e-9);
    // Every anchor is within reach everywhere on the walk (the area is open).
    for (const WifiScan& s : w.anchor_scans) EXPECT_EQ(s.readings.size(), sc.beacons.size());
}

TEST(SimAnchors, ReadingsFollowTheLogDistanceModel) {
    // Averaged over many walks at the start point, each anchor's RSS is its model's at the
    // distance, within the static shadowing and the phone offsets' mean.
    const Scenario& sc = scenario("open_area");
    SimConfig cfg = default_config("open_area");
    cfg.beacon_phone_offset_sigma_db = 0.0;
    std::map<std::string, std::pair<double, int>> sums;
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
        const Walk w = simulate(sc, seed, cfg);
        for (const WifiScan& s : w.anchor_scans) {
            if (s.t_s > cfg.stand_before_s - 0.1) break;  // still standing at the start
            for (const Reading& r : s.readings) sums[r.bssid].first += r.rss, ++sums[r.bssid].second;
        }
    }
    const Environment env(sc);
    for (std::size_t b = 0; b < sc.beacons.size(); ++b) {
        const auto& [sum, n] = sums[sc.beacons[b].id];
        ASSERT_GT(n, 10);
        EXPECT_NEAR(sum / n, env.beacon_mean_rss(b, sc.path.front()), 1.5) << sc.beacons[b].id;
        const double d = std::hypot(distance(sc.beacons[b].at, sc.path.front()), sc.beacons[b].height_m - sc.phone_height_m);
        EXPECT_NEAR(env.beacon_mean_rss(b, sc.path.front()),
                    sc.beacons[b].tx_power_dbm - 10.0 * sc.beacons[b].true_exponent * std::log10(d),
                    3.0 * sc.beacon_shadowing_sigma_db);
    }
}

TEST(SimAnchors, WalkFilesKeepAnchorsAndTheirReadings) {
    const Walk w = simulate(scenario("open_area"), 3, default_config("open_area"));
    std::stringstream buf;
    buf.precision(17);
    write_walk(buf, w);
    const Walk back = read_walk(buf);
    ASSERT_EQ(back.anchors.size(), w.anchors.size());
    for (std::size_t i = 0; i < w.anchors.size(); ++i) {
        EXPECT_EQ(back.anchors[i].id, w.anchors[i].id);
        EXPECT_EQ(back.anchors[i].type, w.anchors[i].type);
        EXPECT_DOUBLE_EQ(back.anchors[i].tx.at.x, w.anchors[i].tx.at.x);
        EXPECT_DOUBLE_EQ(back.anchors[i].tx.dz, w.anchors[i].tx.dz);
        EXPECT_DOUBLE_EQ(back.anchors[i].tx.model.tx_power, w.anchors[i].tx.model.tx_power);
    }
    ASSERT_EQ(back.anchor_scans.size(), w.anchor_scans.size());
    auto by_id = [](const Scan& s) {
        std::map<std::string, double> m;
        for (const Reading& r : s) m[r.bssid] = r.rss;
        return m;
    };
    for (std::size_t i = 0; i < w.anchor_scans.size(); ++i)
        EXPECT_EQ(by_id(back.anchor_scans[i].readings), by_id(w.anchor_scans[i].readings));
    EXPECT_EQ(back.scans.size(), w.scans.size());  // WiFi scans stay WiFi scans
    // Identical fixes from the file as from memory.
    const RangingEvalConfig rc;
    EXPECT_EQ(run_ranging(back, rc).multilateration.size(), run_ranging(w, rc).multilateration.size());
}

TEST(SimAnchors, EachKalmanBeatsItsInputsOnTheMeanError) {
    // Over walks the tuning did not use (seeds 201..205), on the whole track: the filter must
    // be better than the PDR it is driven by and than the fixes it is corrected by.
    const RangingEvalConfig rc;
    std::map<std::string, double> mean;
    for (std::uint64_t seed = 201; seed <= 205; ++seed) {
        const Walk w = simulate(scenario("open_area"), seed, default_config("open_area"));
        const auto steps = run_pdr(w);
        const auto fixes = run_ranging(w, rc);
        ASSERT_GE(fixes.multilateration.size(), 5u);
        auto tracks = run_ranging_methods(steps, fixes, w.start, rc);
        Track pdr{{0.0, w.start}};
        Point p = w.start;
        for (const PdrStep& s : steps) p = pdr::step(p, s.length_m, s.heading_rad), pdr.push_back({s.t_s, p});
        tracks.push_back({"pdr", pdr});
        for (const NamedTrack& t : tracks) mean[t.method] += score(t, w).mean_error_m / 5.0;
    }
    EXPECT_LT(mean["kalman_ranging"], mean["pdr"]);
    EXPECT_LT(mean["kalman_ranging"], mean["multilateration"]);
    EXPECT_LT(mean["kalman_trilateration"], mean["pdr"]);
    EXPECT_LT(mean["kalman_trilateration"], mean["trilateration"]);
    // The tightly coupled filter: the readings it takes one by one, ranged on their own, are
    // multilateration's input.
    EXPECT_LT(mean["ekf_ranging"], mean["pdr"]);
    EXPECT_LT(mean["ekf_ranging"], mean["multilateration"]);
    EXPECT_LT(mean["ekf_ranging"], mean["trilateration"]);
}

}  // namespace
}  // namespace sim_anchors_test
