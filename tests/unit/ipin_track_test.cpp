// The trackers of `locus eval ipin` (tools/ipin_track.hpp) on walks written for the test: the
// known start, dead reckoning by hand, causality (a walk cut at T gives the same estimates up
// to T), and the Kalman filter doing better than the answers it fuses. The default tracker,
// walk_pf, is the server's live track (server_tracks_*_test, cli_replay_ipin_test).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ipin_track.hpp"

namespace ipin_track_test {
namespace {

using namespace locus;
using namespace locus::tools;

// A walk east along y = 0 at 1.2 m/s from t = 10 s: a 0.6 m step every 0.5 s (confirmed at
// its own time), compass pointing east (the venue frame north-up); a WiFi answer every 2 s
// from t = 0, off the truth by up to 4 m in a fixed pattern; pressure at 5 Hz, steady.
struct Synthetic {
    std::vector<ipin::ImuStep> steps;
    std::vector<datasets::ipin::PressureSample> pressure;
    std::vector<double> scan_t;
    std::vector<std::optional<ipin::Fix>> answers;
    double end_s = 70.0;

    static Point truth(double t) { return {1.2 * std::max(0.0, t - 10.0), 0.0}; }

    Synthetic() {
        for (double t = 10.5; t <= end_s; t += 0.5) steps.push_back({t, 0.6, std::numbers::pi / 2});
        for (double t = 0.0; t <= end_s; t += 0.2) pressure.push_back({t, 1000.0});
        for (int i = 0; 2.0 * i <= end_s; ++i) {
            const double t = 2.0 * i;
            const Point p = truth(t);
            scan_t.push_back(t);
            answers.push_back(ipin::Fix{t, 0, {p.x + 4.0 * std::sin(1.7 * i), p.y + 4.0 * std::cos(2.3 * i)}});
        }
    }

    // The walk as the phone knew it at T: nothing stamped after T, ticks up to T.
    Synthetic cut(double t_cut) const {
        Synthetic c = *this;
        c.end_s = t_cut;
        std::erase_if(c.steps, [&](const ipin::ImuStep& s) { return s.t_s > t_cut; });
        std::erase_if(c.pressure, [&](const datasets::ipin::PressureSample& s) { return s.t_s > t_cut; });
        while (!c.scan_t.empty() && c.scan_t.back() > t_cut) {
            c.scan_t.pop_back();
            c.answers.pop_back();
        }
        return c;
    }

    ipin::TrackInput input(std::optional<ipin::Fix> start) const { return {steps, pressure, scan_t, answers, end_s, start, {}, {}}; }
};

const std::vector<fusion::FloorLevel> kFloors = {{0, 0.0, true}, {-2, -5.7, true}};

ipin::TrackerConfig north_up() {
    ipin::TrackerConfig c;
    c.compass_offset_rad = 0.0;
    return c;
}

TEST(IpinTrack, PdrWithAKnownStartStandsOnItThenWalksTheCompass) {
    // Steps every 0.5 s from t = 1 s, 0.8 m each, due east; no answer, no barometer.
    std::vector<ipin::ImuStep> steps;
    for (double t = 1.0; t <= 15.0; t += 0.5) steps.push_back({t, 0.8, std::numbers::pi / 2});
    const ipin::Fix start{5.0, -2, {10.0, 20.0}};
    const ipin::TrackInput in{steps, {}, {}, {}, 12.0, start, {}, {}};
    ipin::TrackerConfig config = north_up();
    config.step_scale = 1.0;  // no answer fits a scale: the steps as detected
    const auto est = ipin::track(ipin::Tracker::pdr, in, {}, config);
    ASSERT_EQ(est.size(), 25u);  // ticks 0, 0.5, ..., 12
    for (const auto& e : est) {
        EXPECT_EQ(e.floor, -2);
        EXPECT_NEAR(e.at.y, 20.0, 1e-9);
        // Before 5 s the steps (the calibration's waving) move nothing; from 5 s on each step
        // stamped at or before the tick counts: 5.0, 5.5, ..., t.
        const double walked = e.t < 5.0 ? 0.0 : 0.8 * (std::floor((e.t - 5.0) / 0.5 + 1e-9) + 1.0);
        EXPECT_NEAR(e.at.x, 10.0 + walked, 1e-9) << "t " << e.t;
    }
    EXPECT_NEAR(est.back().at.x, 10.0 + 0.8 * 15, 1e-9);  // 5.0 … 12.0: 15 steps
}

TEST(IpinTrack, ACutWalkLeavesEveryEarlierEstimateAsItWas) {
    const Synthetic full;
    for (const double t_cut : {9.3, 31.3, 50.0}) {
        const Synthetic cut = full.cut(t_cut);
        for (const auto tracker : {ipin::Tracker::pdr, ipin::Tracker::kalman}) {
            for (const bool known : {false, true}) {
                const std::optional<ipin::Fix> start =
                    known ? std::optional<ipin::Fix>(ipin::Fix{10.0, 0, Synthetic::truth(10.0)}) : std::nullopt;
                const auto a = ipin::track(tracker, full.input(start), kFloors, north_up());
                const auto b = ipin::track(tracker, cut.input(start), kFloors, north_up());
                ASSERT_FALSE(b.empty());
                ASSERT_LE(b.size(), a.size());
                for (std::size_t i = 0; i < b.size(); ++i) {
                    ASSERT_LE(b[i].t, t_cut);
                    EXPECT_EQ(a[i].t, b[i].t);
                    EXPECT_EQ(a[i].floor, b[i].floor);
                    EXPECT_EQ(a[i].at.x, b[i].at.x) << "cut " << t_cut << " tick " << b[i].t;
                    EXPECT_EQ(a[i].at.y, b[i].at.y);
                }
                // The full walk's estimates go on past the cut.
                EXPECT_GT(a.back().t, t_cut);
            }
        }
    }
}

TEST(IpinTrack, KalmanTracksCloserThanTheAnswersItFuses) {
    const Synthetic w;
    const auto est = ipin::track(ipin::Tracker::kalman, w.input(std::nullopt), kFloors, north_up());
    ASSERT_FALSE(est.empty());
    // Without a known start it begins at the first answer (t = 0).
    EXPECT_EQ(est.front().t, 0.0);
    double filter = 0.0, answers = 0.0;
    int n = 0;
    for (const auto& e : est) {
        if (e.t < 20.0 || std::fmod(e.t, 2.0) != 0.0) continue;  // after it settled, at the answers' instants
        const auto& a = w.answers[static_cast<std::size_t>(e.t / 2.0)];
        filter += distance(e.at, Synthetic::truth(e.t));
        answers += distance(a->at, Synthetic::truth(e.t));
        EXPECT_EQ(e.floor, 0);
        ++n;
    }
    ASSERT_GT(n, 10);
    // The answers are 4 m off on average here (the pattern's radius); the steps carry the walk
    // between them.
    EXPECT_LT(filter / n, 0.6 * answers / n) << "filter " << filter / n << " answers " << answers / n;
}

// The steps of Synthetic with no WiFi answer, from a known start at its truth at 10 s, and a
// GNSS fix every second from 20 s on, `north_m` north of the truth, accuracy 10 m.
struct GnssWalk {
    Synthetic w;
    std::vector<ipin::GnssFix> gnss;
    const ipin::Fix start{10.0, 0, Synthetic::truth(10.0)};

    explicit GnssWalk(double north_m) {
        for (double t = 20.0; t <= w.end_s; t += 1.0) gnss.push_back({t, {Synthetic::truth(t).x, north_m}, 10.0});
    }
    std::vector<ipin::Fix> track(ipin::Tracker tracker, bool with_gnss) const {
        ipin::TrackInput in{w.steps, w.pressure, {}, {}, w.end_s, start, {}, {}};
        if (with_gnss) in.gnss = gnss;
        return ipin::track(tracker, in, kFloors, north_up());
    }
};

TEST(IpinTrack, GnssPullsKalmanAndLeavesPdrAlone) {
    const GnssWalk walk(8.0);
    for (const auto tracker : {ipin::Tracker::kalman}) {
        const auto without = walk.track(tracker, false), with = walk.track(tracker, true);
        ASSERT_EQ(without.size(), with.size());
        EXPECT_NEAR(without.back().at.y, 0.0, 1.5);
        EXPECT_GT(with.back().at.y, without.back().at.y + 3.0) << static_cast<int>(tracker);  // drawn to the fixes 8 m north
        EXPECT_LT(with.back().at.y, 10.0) << static_cast<int>(tracker);
        // Before the first fix nothing differs.
        for (std::size_t i = 0; i < with.size() && with[i].t < 20.0; ++i) EXPECT_EQ(with[i].at.y, without[i].at.y);
    }
    const auto pdr = walk.track(ipin::Tracker::pdr, true), pdr_without = walk.track(ipin::Tracker::pdr, false);
    ASSERT_EQ(pdr.size(), pdr_without.size());
    for (std::size_t i = 0; i < pdr.size(); ++i) EXPECT_EQ(pdr[i].at.y, pdr_without[i].at.y);
}

TEST(IpinTrack, KalmanGatesAGnssFixFarFromItsEstimate) {
    const GnssWalk walk(200.0);  // far beyond σ 10 m and the filter's own spread
    const auto without = walk.track(ipin::Tracker::kalman, false), with = walk.track(ipin::Tracker::kalman, true);
    ASSERT_EQ(without.size(), with.size());
    for (std::size_t i = 0; i < with.size(); ++i) {
        EXPECT_EQ(with[i].at.x, without[i].at.x);
        EXPECT_EQ(with[i].at.y, without[i].at.y);
    }
}

TEST(IpinTrack, LogGnssTakesEachFixOnceAndOnlyWithAnAccuracy) {
    datasets::ipin::Log log;
    const auto fix = [](double app, double sensor, double lat, double accuracy) {
        datasets::ipin::Gnss g;
        g.app_s = app;
        g.sensor_s = sensor;
        g.lat_deg = lat;
        g.lon_deg = 11.0;
        g.accuracy_m = accuracy;
        return g;
    };
    log.gnss = {fix(1.0, 100.0, 49.0, 4.0), fix(1.01, 100.0, 49.0, 4.0),  // one fix, logged twice
                fix(2.0, 101.0, 49.1, 0.0),                            // no accuracy
                fix(3.0, 102.0, 49.2, 6.0)};
    const auto got = ipin::log_gnss(log, [](double lat, double lon) { return Point{lat, lon}; });
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0].t, 1.0);
    EXPECT_EQ(got[0].at.x, 49.0);
    EXPECT_EQ(got[0].accuracy_m, 4.0);
    EXPECT_EQ(got[1].t, 3.0);
    EXPECT_EQ(got[1].at.x, 49.2);
}

TEST(IpinTrack, BeaconFixesAreTheStrongReadingsOfTheMapsBeaconsOncePerInterval) {
    const std::vector<ipin::Beacon> beacons = {{Bssid("be:ac:20:23:00:01"), 0, {5.0, 6.0}},
                                               {Bssid("be:ac:20:23:00:04"), -2, {-3.0, 2.0}}};
    const std::vector<ipin::BleReading> readings = {
        {1.0, Bssid("BE:AC:20:23:00:01"), -65.0},  // strong: a fix (the MAC as logged, upper case)
        {1.5, Bssid("be:ac:20:23:00:01"), -60.0},  // within 2 s of the last: the same look
        {2.0, Bssid("be:ac:20:23:00:04"), -66.0},  // below -65 dBm
        {2.5, Bssid("be:ac:20:23:00:09"), -50.0},  // not the map's
        {3.2, Bssid("be:ac:20:23:00:01"), -65.0},  // 2.2 s after the first: a new look, at the threshold
        {4.0, Bssid("be:ac:20:23:00:04"), -55.0},
    };
    const auto got = ipin::beacon_fixes(readings, beacons, ipin::TrackerConfig{});
    ASSERT_EQ(got.size(), 3u);
    EXPECT_EQ(got[0].t, 1.0);
    EXPECT_EQ(got[0].floor, 0);
    EXPECT_EQ(got[0].at.x, 5.0);
    EXPECT_EQ(got[1].t, 3.2);
    EXPECT_EQ(got[2].t, 4.0);
    EXPECT_EQ(got[2].floor, -2);
    EXPECT_EQ(got[2].at.y, 2.0);
}

// GnssWalk's steps and start, with a beacon 8 m north of the walk heard every 3 s from 20 s.
TEST(IpinTrack, ABeaconPullsKalmanAndNamesItsFloor) {
    const GnssWalk walk(0.0);
    std::vector<ipin::BeaconFix> ble;
    for (double t = 20.0; t <= walk.w.end_s; t += 3.0) ble.push_back({t, -2, {Synthetic::truth(t).x, 8.0}});
    const auto run = [&](ipin::Tracker tracker, bool with_ble, const std::vector<fusion::FloorLevel>& floors) {
        ipin::TrackInput in{walk.w.steps, walk.w.pressure, {}, {}, walk.w.end_s, walk.start, {}, {}};
        if (with_ble) in.ble = ble;
        return ipin::track(tracker, in, floors, north_up());
    };
    for (const auto tracker : {ipin::Tracker::kalman}) {
        const auto without = run(tracker, false, {}), with = run(tracker, true, {});
        ASSERT_EQ(without.size(), with.size());
        EXPECT_GT(with.back().at.y, without.back().at.y + 3.0) << static_cast<int>(tracker);
        EXPECT_LT(with.back().at.y, 10.0) << static_cast<int>(tracker);
        // Without a barometer the beacon's floor is the track's from its first reading on.
        EXPECT_EQ(without.back().floor, 0);
        EXPECT_EQ(with.back().floor, -2);
        for (const auto& e : with) EXPECT_EQ(e.floor, e.t < 20.0 ? 0 : -2) << e.t;
    }
    // pdr takes no position measurement but the floor.
    const auto pdr = run(ipin::Tracker::pdr, true, {}), pdr_without = run(ipin::Tracker::pdr, false, {});
    ASSERT_EQ(pdr.size(), pdr_without.size());
    for (std::size_t i = 0; i < pdr.size(); ++i) EXPECT_EQ(pdr[i].at.y, pdr_without[i].at.y);
}

TEST(IpinTrack, LogBleKeepsEveryBeaconReadingInTimeOrder) {
    datasets::ipin::Log log;
    const auto ad = [](double t, const char* mac, double rss) {
        datasets::ipin::Ble4 b;
        b.app_s = t;
        b.mac = Bssid(mac);
        b.rssi_dbm = rss;
        return b;
    };
    log.ble4 = {ad(2.0, "be:ac:20:23:00:02", -80.0), ad(1.0, "be:ac:20:23:00:01", -60.0), ad(2.0, "be:ac:20:23:00:03", -70.0)};
    const auto got = ipin::log_ble(log);
    ASSERT_EQ(got.size(), 3u);
    EXPECT_EQ(got[0].t, 1.0);
    EXPECT_EQ(got[0].rss_dbm, -60.0);
    EXPECT_EQ(got[1].mac, Bssid("be:ac:20:23:00:02"));  // equal times keep the file's order
    EXPECT_EQ(got[2].mac, Bssid("be:ac:20:23:00:03"));
}

}  // namespace
}  // namespace ipin_track_test
