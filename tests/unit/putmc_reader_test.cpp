// The PUTMC reader on hand-written snippets and the tiny fixture (tests/fixtures/putmc: the
// survey's first 4 points, 11 s of walk 1 with its first 3 scans, a 305 × 105 px drawing).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "datasets/putmc.hpp"
#include "build_paths.hpp"

namespace putmc_reader_test {
namespace {

namespace putmc = locus::datasets::putmc;

std::string error_of(auto&& f) {
    try {
        f();
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

const std::string kFixtures = std::string(LOCUS_TEST_FIXTURES) + "/putmc";

TEST(PutmcReader, ParsesAccAndOrient) {
    const auto acc = putmc::parse_acc("1000000000 0.5 1.5 9.8\n\n2500000000 -1 0 9\n", "acc.map");
    ASSERT_EQ(acc.size(), 2u);
    EXPECT_DOUBLE_EQ(acc[1].t_s, 2.5);
    EXPECT_DOUBLE_EQ(acc[0].a.y, 1.5);
    const auto o = putmc::parse_orient("1000000000 0 0 0 1.2 0.17\n", "orient.map");
    ASSERT_EQ(o.size(), 1u);
    EXPECT_DOUBLE_EQ(o[0].qw, 1.0);  // normalised
    EXPECT_DOUBLE_EQ(o[0].accuracy_rad, 0.17);
}

TEST(PutmcReader, ErrorsNameFileAndLine) {
    EXPECT_EQ(error_of([] { putmc::parse_acc("2000000000 0 0 9\n1000000000 0 0 9\n", "w/acc.map"); }).rfind("w/acc.map:2: timestamp goes back", 0), 0u);
    EXPECT_NE(error_of([] { putmc::parse_acc("1 0 nan 9\n", "acc.map"); }).find("acc.map:1: ay is not finite"), std::string::npos);
    EXPECT_NE(error_of([] { putmc::parse_acc("1 0 9\n", "acc.map"); }).find("acc.map:1: expected"), std::string::npos);
    EXPECT_NE(error_of([] { putmc::parse_orient("1 0 0 0 0 0.1\n", "o.map"); }).find("o.map:1: quaternion"), std::string::npos);
    // A block promising 3 readings that ends after 1.
    const std::string truncated = "5 0 3\naa:bb:cc:dd:ee:01\tnet\t-60.0 2412 1\n";
    EXPECT_NE(error_of([&] { putmc::parse_wifi(truncated, "wifi.map", true); }).find("wifi.map:1: truncated"), std::string::npos);
    // A block cut short by the next header.
    const std::string cut = "5 0 2\naa:bb:cc:dd:ee:01\tnet\t-60.0 2412 1\n9 1 1\naa:bb:cc:dd:ee:01\tnet\t-61.0 2412 1\n";
    EXPECT_NE(error_of([&] { putmc::parse_wifi(cut, "wifi.map", true); }).find("wifi.map:3: expected a reading"), std::string::npos);
    const std::string unsorted = "9 0 0\n5 1 0\n";
    EXPECT_NE(error_of([&] { putmc::parse_wifi(unsorted, "wifi.map", true); }).find("wifi.map:2: timestamp goes back"), std::string::npos);
    const std::string nan_rss = "5 0 1\naa:bb:cc:dd:ee:01\tnet\tnan 2412 1\n";
    EXPECT_NE(error_of([&] { putmc::parse_wifi(nan_rss, "wifi.map", true); }).find("wifi.map:2: rss is not finite"), std::string::npos);
    EXPECT_NE(error_of([] { putmc::parse_positions("0 1 2\n0 3 4\n", "p.map"); }).find("p.map:2: id 0 listed twice"), std::string::npos);
    EXPECT_NE(error_of([] { putmc::parse_scale("-3\n", "s.map"); }).find("s.map:1:"), std::string::npos);
    EXPECT_NE(error_of([] { putmc::parse_scale("", "s.map"); }).find("empty"), std::string::npos);
}

TEST(PutmcReader, WifiBlocksKeepSsidWithSpacesAndEmpty) {
    const std::string text = "-1 7 2\nAA:BB:CC:DD:EE:01\tmy net\t-60.0 2412 1\naa:bb:cc:dd:ee:02\t\t-70.5 5180 2\n";
    const auto scans = putmc::parse_wifi(text, "wifi.map", false);
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].loc_id, 7);
    EXPECT_EQ(scans[0].t_s, -1.0);
    ASSERT_EQ(scans[0].readings.size(), 2u);
    EXPECT_EQ(scans[0].readings[0].bssid.str(), "aa:bb:cc:dd:ee:01");
    EXPECT_DOUBLE_EQ(scans[0].readings[1].rss, -70.5);
}

TEST(PutmcReader, AndroidAzimuth) {
    // Identity: the phone's top points north.
    EXPECT_NEAR(putmc::android_azimuth({0, 0, 0, 0, 1, 0}), 0.0, 1e-12);
    // Turned 90° counter-clockwise about the up axis (seen from above): the top points west.
    const double h = std::sqrt(0.5);
    EXPECT_NEAR(putmc::android_azimuth({0, 0, 0, h, h, 0}), -std::numbers::pi / 2, 1e-12);
    EXPECT_NEAR(putmc::android_azimuth({0, 0, 0, -h, h, 0}), std::numbers::pi / 2, 1e-12);
}

TEST(PutmcReader, ReadsTheFixture) {
    const auto survey = putmc::read_survey(kFixtures + "/map");
    EXPECT_NEAR(survey.px_per_m, 2.8398863, 1e-6);
    ASSERT_EQ(survey.scans.size(), 4u);
    EXPECT_EQ(survey.scans[0].readings.size(), 23u);
    EXPECT_NEAR(survey.at_of(1).x, 30.4172467139, 1e-9);

    const auto dirs = putmc::walk_dirs(kFixtures);
    ASSERT_EQ(dirs.size(), 1u);
    const auto walk = putmc::read_walk(dirs[0]);
    EXPECT_EQ(walk.name, "tiny_walk");
    EXPECT_EQ(walk.scans.size(), 3u);
    EXPECT_GT(walk.acc.size(), 1000u);
    EXPECT_NEAR(walk.scans[1].t_s, 488.551418694, 1e-9);
    EXPECT_NEAR(walk.truth_of(walk.scans[2]).x, 68.45168629973317, 1e-9);
    EXPECT_NE(error_of([] { putmc::read_walk(kFixtures + "/nowhere"); }).find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace putmc_reader_test
