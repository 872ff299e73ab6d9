// The pieces of `locus import ipin` / `locus eval ipin` / `locus survey walk` that read no
// server: the beacons file, the landmarks CSV, the venue frame, the competition's scoring and
// the Hazen percentile. Expected values are worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "ipin_eval.hpp"
#include "ipin_venue.hpp"
#include "locus/metrics.hpp"
#include "datasets/walk_files.hpp"
#include "walk_survey.hpp"

namespace ipin_import_test {
namespace {

using namespace locus;
using namespace locus::tools;

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

TEST(IpinImport, ReadsTheBeaconsFile) {
    const auto b = datasets::parse_ipin_beacons(
        "bleID,Lat,Lon,floor\n\"BLE1\",49.46129,11.11120,00\r\n\"BLE3\",49.46130,11.11152,-2\n", "B.csv");
    ASSERT_EQ(b.size(), 2u);
    EXPECT_EQ(b[0].name, "BLE1");
    EXPECT_EQ(b[0].number, 1);
    EXPECT_EQ(b[0].floor, 0);
    EXPECT_DOUBLE_EQ(b[1].lat, 49.46130);
    EXPECT_EQ(b[1].floor, -2);
    EXPECT_EQ(b[1].line, 3);
    EXPECT_EQ(ipin::beacon_mac(3), "be:ac:20:23:00:03");
}

TEST(IpinImport, BeaconsFileErrorsNameFileAndLine) {
    EXPECT_EQ(message_of([] { datasets::parse_ipin_beacons("id,Lat,Lon,floor\n", "B.csv"); }),
              "B.csv:1: the header must be bleID,Lat,Lon,floor");
    EXPECT_EQ(message_of([] { datasets::parse_ipin_beacons("bleID,Lat,Lon,floor\n\"BLE1\",49.4,11.1,0\n\"BLE2\",x,11.1,0\n", "B.csv"); }),
              "B.csv:3: 'Lat' is not a latitude: 'x'");
    EXPECT_EQ(message_of([] { datasets::parse_ipin_beacons("bleID,Lat,Lon,floor\n\"BLE1\",49.4,11.1\n", "B.csv"); }),
              "B.csv:2: 3 cells, expected 4 (bleID,Lat,Lon,floor)");
    EXPECT_EQ(message_of([] { datasets::parse_ipin_beacons("bleID,Lat,Lon,floor\n\"BLE1\",49.4,11.1,0.5\n", "B.csv"); }),
              "B.csv:2: 'floor' is not a whole number: '0.5'");
    EXPECT_EQ(message_of([] { datasets::parse_ipin_beacons("bleID,Lat,Lon,floor\nBLE1,49.4,11.1,0\nBLE1,49.4,11.1,0\n", "B.csv"); }),
              "B.csv:3: 'BLE1' is given twice");
    EXPECT_EQ(message_of([] { datasets::parse_ipin_beacons("", "B.csv"); }), "B.csv: empty (no bleID,Lat,Lon,floor header)");
}

TEST(IpinImport, LandmarksCsv) {
    const auto l = datasets::parse_landmarks_csv("x,y,t,floor\n1,2,10.5,0\n\n3,4,12,-2\n", "L.csv");
    ASSERT_EQ(l.size(), 2u);
    EXPECT_DOUBLE_EQ(l[0].t, 10.5);
    EXPECT_DOUBLE_EQ(l[0].at.x, 1.0);
    EXPECT_DOUBLE_EQ(l[0].at.y, 2.0);
    EXPECT_EQ(l[1].floor, -2);
    EXPECT_EQ(message_of([] { datasets::parse_landmarks_csv("t,floor,x\n", "L.csv"); }), "L.csv:1: the header must name the columns t, floor, x and y");
    EXPECT_EQ(message_of([] { datasets::parse_landmarks_csv("t,floor,x,y\n1,0,1,1\n2,0,nan,1\n", "L.csv"); }),
              "L.csv:3: 'x' is not a finite number: 'nan'");
    EXPECT_EQ(message_of([] { datasets::parse_landmarks_csv("t,floor,x,y\n5,0,1,1\n4,0,1,1\n", "L.csv"); }),
              "L.csv:3: landmarks must be in time order (t goes back)");
    EXPECT_EQ(message_of([] { datasets::parse_landmarks_csv("t,floor,x,y\n5,0.5,1,1\n", "L.csv"); }),
              "L.csv:2: 'floor' must be a whole number within ±1000");
    EXPECT_EQ(message_of([] { datasets::parse_landmarks_csv("t,floor,x,y\n5,0,1\n", "L.csv"); }), "L.csv:2: 3 cells, the header has 4");
}

TEST(IpinImport, VenueFrameIsEastNorthAboutTheOrigin) {
    const geo::FloorToEarth frame(ipin::venue_georeference());
    const Point o = frame.to_floor({ipin::kOriginLat, ipin::kOriginLon});
    EXPECT_NEAR(o.x, ipin::kOriginX, 1e-6);
    EXPECT_NEAR(o.y, ipin::kOriginY, 1e-6);
    // 1e-4 degrees of latitude north: 6,372,360 m × 1e-4 × π/180 = 11.122 m (the README's radius).
    const Point n = frame.to_floor({ipin::kOriginLat + 1e-4, ipin::kOriginLon});
    EXPECT_NEAR(n.x, ipin::kOriginX, 0.01);
    EXPECT_NEAR(n.y - ipin::kOriginY, 11.122, 0.01);
    // 1e-4 degrees of longitude east: 6,390,503 m × cos(49.46115°) × 1e-4 × π/180 = 7.250 m.
    const Point e = frame.to_floor({ipin::kOriginLat, ipin::kOriginLon + 1e-4});
    EXPECT_NEAR(e.x - ipin::kOriginX, 7.250, 0.01);
    EXPECT_NEAR(e.y, ipin::kOriginY, 0.01);
}

TEST(IpinImport, TrialLabels) {
    EXPECT_EQ(ipin::trial_label("/d/trials/IPIN2023_T3_TrainingTrial05_repetition03.txt"), "T05_R03");
    EXPECT_EQ(ipin::trial_label("walk.txt"), "walk");
}

TEST(IpinEval, HazenPercentileIsMatlabsQuantile) {
    // MATLAB: quantile([1 2 3 4], 0.75) = 3.5; quantile([1 2 3 4 10], 0.75) = 5.5; quantile([1 2], 0.75) = 2.
    const std::vector<double> a{1, 2, 3, 4}, b{1, 2, 3, 4, 10}, c{1, 2}, one{7};
    EXPECT_DOUBLE_EQ(metrics::percentile_hazen(a, 0.75), 3.5);
    EXPECT_DOUBLE_EQ(metrics::percentile_hazen(b, 0.75), 5.5);
    EXPECT_DOUBLE_EQ(metrics::percentile_hazen(c, 0.75), 2.0);
    EXPECT_DOUBLE_EQ(metrics::percentile_hazen(one, 0.75), 7.0);
    EXPECT_DOUBLE_EQ(metrics::percentile_hazen(a, 0.0), 1.0);
    EXPECT_TRUE(std::isnan(metrics::percentile_hazen(std::vector<double>{}, 0.75)));
}

TEST(IpinEval, LatestEstimateAtMostALagAfterTheInstant) {
    const std::vector<ipin::Fix> est = {{10.0, 0, {0, 0}}, {20.005, 0, {3, 4}}, {30.02, -2, {0, 0}}};
    const std::vector<ipin::Fix> truth = {{5.0, 0, {0, 0}},    // nothing yet: unscored
                                          {15.0, 0, {0, 1}},   // the t=10 estimate: 1 m
                                          {20.0, 0, {0, 0}},   // t=20.005 is within 0.01 s after: 5 m
                                          {30.0, -2, {3, 4}}}; // t=30.02 is too late; t=20.005 on floor 0: 0 + 15 × 2
    const auto r = ipin::score_instants(est, truth);
    EXPECT_EQ(r.unscored, 1u);
    ASSERT_EQ(r.errors.size(), 3u);
    EXPECT_DOUBLE_EQ(r.errors[0], 1.0);
    EXPECT_DOUBLE_EQ(r.errors[1], 5.0);
    EXPECT_DOUBLE_EQ(r.errors[2], 30.0);
    EXPECT_EQ(r.floor_hits, 2u);
    const auto f = ipin::figures(r);
    EXPECT_DOUBLE_EQ(f["p75_m"].get<double>(), 23.75);  // Hazen over {1, 5, 30}: index 0.75·3 − 0.5 = 1.75 → 5 + 0.75·25
}

TEST(WalkJobs, BinsBecomeNamedRpsOnTheirFloorsRadioMap) {
    Walk w;
    w.source = "walk.txt";
    w.stem = "walk";
    w.content = "0123456789abcdef";
    // Floor 0 from (0,0) to (10,0) over 10 s, then floor 1 (not mapped) from t = 20.
    w.landmarks = {{0, 0, {0, 0}}, {10, 0, {10, 0}}, {20, 1, {10, 0}}, {30, 1, {10, 10}}};
    for (double t : {-1.0, 1.0, 3.0, 9.0, 15.0, 25.0}) {
        w.scan_times.push_back(t);
        w.scans.push_back({Reading{"wifi", Bssid("aa:bb:cc:dd:ee:ff"), -50.0 - t}});
    }
    WalkCounts counts;
    const auto jobs = walk_jobs(w, {{0, 7}}, 5.0, counts);
    EXPECT_EQ(counts.scans, 6u);
    EXPECT_EQ(counts.before_first, 1u);
    EXPECT_EQ(counts.floor_change, 1u);    // t = 15, on the stairs
    EXPECT_EQ(counts.unmapped_floor, 1u);  // t = 25, floor 1
    EXPECT_EQ(counts.placed, 3u);
    // Path 1 and 3 m share a bin; 9 m starts the next.
    ASSERT_EQ(jobs.size(), 2u);
    EXPECT_EQ(jobs[0].name, "walk 5m #001 01234567");
    EXPECT_EQ(jobs[1].name, "walk 5m #002 01234567");
    EXPECT_EQ(jobs[0].radiomap_id, 7);
    ASSERT_TRUE(jobs[0].at);
    EXPECT_DOUBLE_EQ(jobs[0].at->x, 2.0);
    EXPECT_DOUBLE_EQ(jobs[0].at->y, 0.0);
    ASSERT_EQ(jobs[0].scans.size(), 2u);
    EXPECT_DOUBLE_EQ(jobs[0].scans[1][0].rss, -53.0);  // the t = 3 s scan
    EXPECT_EQ(jobs[0].upload_id, "walk-0123456789abcdef-5");
    EXPECT_EQ(jobs[0].source, "walk.txt");
    EXPECT_EQ(counts.rps_per_floor.at(0), 2u);
    EXPECT_EQ(cell_text(2.5), "2.5");
    EXPECT_EQ(cell_text(0), "0");
}

}  // namespace
}  // namespace ipin_import_test
