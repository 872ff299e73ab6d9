// The UJIIndoorLoc reader on a five-row fixture whose RP statistics are worked out by hand.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

// The reader lives with the CLI sources, which are not a library; compile it in here.
#include <fstream>

#include "datasets/uji_csv.hpp"
#include "build_paths.hpp"

namespace match_uji_csv_test {
namespace {

namespace uji = locus::datasets::uji;

const std::string kTiny = std::string(LOCUS_TEST_FIXTURES) + "/uji_tiny.csv";

TEST(UjiCsv, ReadsRowsSkippingNotDetectedAndBadValues) {
    const uji::Data d = uji::read_file(kTiny);
    ASSERT_EQ(d.waps, (std::vector<std::string>{"WAP001", "WAP002", "WAP003"}));
    ASSERT_EQ(d.rows.size(), 5u);
    const auto& r0 = d.rows[0];
    ASSERT_EQ(r0.heard.size(), 2u);  // WAP002 is 100 = not detected
    EXPECT_EQ(r0.heard[0].first, 0);
    EXPECT_DOUBLE_EQ(r0.heard[0].second, -50.0);
    EXPECT_EQ(r0.heard[1].first, 2);
    EXPECT_DOUBLE_EQ(r0.heard[1].second, -70.0);
    EXPECT_DOUBLE_EQ(r0.longitude, 10.5);
    EXPECT_DOUBLE_EQ(r0.latitude, 20.5);
    EXPECT_EQ(r0.floor, 0);
    EXPECT_EQ(r0.building, 1);
    EXPECT_EQ(r0.space_id, 101);
    EXPECT_EQ(r0.relative_position, 2);
    EXPECT_EQ(r0.user_id, 1);
    EXPECT_EQ(r0.phone_id, 3);
    EXPECT_EQ(r0.timestamp, 1000);
    // -130 dBm is outside [-120, 0]: a bad sample, dropped like "not detected".
    ASSERT_EQ(d.rows[2].heard.size(), 1u);
    EXPECT_EQ(d.rows[2].heard[0].first, 1);
    EXPECT_TRUE(d.rows[3].heard.empty());
}

TEST(UjiCsv, ScanUsesNormalisedWapNames) {
    const uji::Data d = uji::read_file(kTiny);
    const locus::Scan s = uji::scan_of(d, d.rows[1]);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s[0].bssid, "wap001");
    EXPECT_EQ(s[0].type, "wifi");
    EXPECT_DOUBLE_EQ(s[0].rss, -54.0);
    EXPECT_EQ(s[1].bssid, "wap002");
}

TEST(UjiCsv, GroupsRowsIntoReferencePoints) {
    const uji::Data d = uji::read_file(kTiny);
    const auto rps = uji::group_reference_points(d);
    ASSERT_EQ(rps.size(), 3u);
    // Ordered by (building, floor, lon, lat): building 0 first.
    EXPECT_EQ(rps[0].building, 0);
    EXPECT_EQ(rps[0].rows, (std::vector<std::size_t>{4}));

    const auto& a = rps[1];  // building 1 floor 0 at (10.5, 20.5): rows 0 and 1
    EXPECT_EQ(a.building, 1);
    EXPECT_EQ(a.floor, 0);
    EXPECT_EQ(a.rows, (std::vector<std::size_t>{0, 1}));
    ASSERT_EQ(a.measurements.size(), 3u);
    EXPECT_EQ(a.measurements[0].bssid, "wap001");
    EXPECT_DOUBLE_EQ(a.measurements[0].stats.mean, -52.0);     // (-50 - 54) / 2
    EXPECT_DOUBLE_EQ(a.measurements[0].stats.variance, 4.0);   // ((2)² + (2)²) / 2
    EXPECT_EQ(a.measurements[0].stats.count, 2);
    EXPECT_EQ(a.measurements[1].bssid, "wap002");
    EXPECT_DOUBLE_EQ(a.measurements[1].stats.mean, -80.0);
    EXPECT_EQ(a.measurements[1].stats.count, 1);                // heard in one of two scans
    EXPECT_DOUBLE_EQ(a.measurements[2].stats.mean, -70.0);

    const auto& b = rps[2];  // floor 1 at (30, 40): one row heard WAP002, one heard nothing
    EXPECT_EQ(b.rows.size(), 2u);
    ASSERT_EQ(b.measurements.size(), 1u);
    EXPECT_EQ(b.measurements[0].bssid, "wap002");
    EXPECT_EQ(b.measurements[0].stats.count, 1);
}

TEST(UjiCsv, GroupsOnlyTheGivenRows) {
    const uji::Data d = uji::read_file(kTiny);
    const auto rps = uji::group_reference_points(d, {1, 2});
    ASSERT_EQ(rps.size(), 2u);
    EXPECT_DOUBLE_EQ(rps[0].measurements[0].stats.mean, -54.0);
    EXPECT_EQ(rps[0].measurements[0].stats.count, 1);
}

TEST(UjiCsv, RejectsMalformedInputNamingTheLine) {
    const std::string header = "WAP001,LONGITUDE,LATITUDE,FLOOR,BUILDINGID,SPACEID,RELATIVEPOSITION,USERID,PHONEID,TIMESTAMP\n";
    EXPECT_NO_THROW(uji::parse(header + "-50,1,2,0,0,0,1,1,1,5\n"));
    try {
        uji::parse(header + "-50,1,2,0,0,0,1,1,1,5\n-50,1,2,0,0,0,1,1,1\n");
        FAIL() << "a short line must be rejected";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
    }
    EXPECT_THROW(uji::parse(header + "abc,1,2,0,0,0,1,1,1,5\n"), std::runtime_error);
    EXPECT_THROW(uji::parse("WAP001,X,Y\n-50,1,2\n"), std::runtime_error);
    EXPECT_THROW(uji::read_file(kTiny + ".missing"), std::runtime_error);
}

TEST(UjiCsv, RealTrainingFileHas933ReferencePoints) {
    const std::string path = std::string(LOCUS_DATA_DIR) + "/ujiindoorloc/trainingData.csv";
    if (!std::ifstream(path)) GTEST_SKIP() << "UJIIndoorLoc not found at " << path;
    const uji::Data d = uji::read_file(path);
    EXPECT_EQ(d.waps.size(), 520u);
    EXPECT_EQ(d.rows.size(), 19937u);
    EXPECT_EQ(uji::group_reference_points(d).size(), 933u);
}

// Raw fingerprints: one one-scan RP per row, in the given order, nothing averaged; the two
// scans of the first position stay two RPs (their mean would be -52 dBm for WAP001).
TEST(UjiCsv, RawRpsAreOneScanRpsPerRow) {
    const uji::Data d = uji::read_file(kTiny);
    const auto all = uji::raw_rps(d);
    ASSERT_EQ(all.size(), 5u);
    EXPECT_EQ(all[0].rp.id, 1);
    EXPECT_EQ(all[0].rp.scans, 1);
    ASSERT_EQ(all[0].rp.measurements.size(), 2u);
    EXPECT_EQ(all[0].rp.measurements[0].bssid.str(), "wap001");
    EXPECT_DOUBLE_EQ(all[0].rp.measurements[0].stats.mean, -50.0);
    EXPECT_EQ(all[0].rp.measurements[0].stats.count, 1);
    EXPECT_DOUBLE_EQ(all[0].rp.measurements[0].stats.variance, 0.0);
    EXPECT_DOUBLE_EQ(all[1].rp.measurements[0].stats.mean, -54.0);
    EXPECT_EQ(all[0].floor_id, uji::floor_id(1, 0));
    EXPECT_EQ(all[4].building_id, 0);
    EXPECT_TRUE(all[3].rp.measurements.empty());  // a row hearing nothing is an empty RP

    const auto some = uji::raw_rps(d, {4, 1});
    ASSERT_EQ(some.size(), 2u);
    EXPECT_EQ(some[0].rp.id, 1);
    EXPECT_DOUBLE_EQ(some[0].rp.at.x, 5.0);
    EXPECT_DOUBLE_EQ(some[1].rp.measurements[1].stats.mean, -80.0);
}

// The yardstick's "min": the lowest valid reading (-130 is a bad sample, already dropped).
TEST(UjiCsv, MinRssIsTheLowestValidReading) {
    const uji::Data d = uji::read_file(kTiny);
    EXPECT_EQ(uji::min_rss(d), -80.0);
    EXPECT_EQ(uji::min_rss(d, {2}), -60.0);
    EXPECT_EQ(uji::min_rss(d, {3}), std::nullopt);
}

}  // namespace
}  // namespace match_uji_csv_test
