// FIND3 and Anyplace readers and the degree-to-metre projection.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "datasets/survey_sources.hpp"
#include "build_paths.hpp"

namespace survey_sources_test {
namespace {

using namespace locus;
using namespace locus::datasets::survey;

TEST(Find3, LabelsBecomeGroupsOfScans) {
    const std::string text =
        R"({"t":1,"f":"fam","d":"x","l":"kitchen","s":{"wifi":{"AA:BB:CC:DD:EE:01":-50,"aa:bb:cc:dd:ee:02":-60}}})" "\n"
        R"({"t":2,"f":"fam","d":"x","l":"office","s":{"wifi":{"aa:bb:cc:dd:ee:01":-70},"bluetooth":{"tag":-80}}})" "\n"
        R"({"t":3,"f":"fam","d":"x","s":{"wifi":{"aa:bb:cc:dd:ee:01":-70}}})" "\n"  // no label
        R"({"t":4,"f":"fam","d":"x","l":"office","s":{"wifi":{"aa:bb:cc:dd:ee:01":20}}})" "\n"  // bad rss
        R"({"t":5,"f":"fam","d":"x","l":"kitchen","s":{"wifi":{"aa:bb:cc:dd:ee:01":-52}}})" "\n";
    const auto d = parse_find3(text);
    EXPECT_EQ(d.family, "fam");
    ASSERT_EQ(d.errors.size(), 2u);
    EXPECT_EQ(d.errors[0].line, 3u);
    EXPECT_EQ(d.errors[1].line, 4u);
    ASSERT_EQ(d.by_label.size(), 2u);
    EXPECT_EQ(d.by_label.at("kitchen").size(), 2u);
    ASSERT_EQ(d.by_label.at("office").size(), 1u);
    const auto& office = d.by_label.at("office")[0];
    ASSERT_EQ(office.size(), 2u);
    // nlohmann orders the sensor keys, so "bluetooth" readings come first.
    EXPECT_EQ(office[0].type, "ble");
    EXPECT_EQ(office[0].bssid, "tag");
    EXPECT_EQ(office[1].type, "wifi");
    EXPECT_EQ(d.by_label.at("kitchen")[0][0].bssid, "aa:bb:cc:dd:ee:01");
    EXPECT_EQ(d.scans, 3u);
    EXPECT_EQ(d.readings, 5u);
}

TEST(Anyplace, LinesCommentsAndErrors) {
    const std::string text =
        "# comment\n"
        "1434481521016 40.44136598711851 -80.00646941363811 0.0 C4:10:8A:55:F0:08 -69 0\n"
        "1434481521016 40.44136598711851 -80.00646941363811 0.0 c4:10:8a:15:f0:09 -70\n"  // 6 fields
        "1434481521016 40.4 -80.0 0.0 c4:10:8a:15:f0:09 abc 0\n"
        "1434481521017 40.4 -80.0 12.5 c4:10:8a:15:f0:09 -71 1\n";
    const auto d = parse_anyplace(text);
    ASSERT_EQ(d.errors.size(), 2u);
    EXPECT_EQ(d.errors[0].line, 3u);
    EXPECT_EQ(d.errors[1].line, 4u);
    ASSERT_EQ(d.lines.size(), 2u);
    EXPECT_EQ(d.lines[0].bssid, "c4:10:8a:55:f0:08");
    EXPECT_EQ(d.lines[0].floor, "0");
    EXPECT_DOUBLE_EQ(d.lines[1].rss, -71.0);
    EXPECT_EQ(d.lines[1].floor, "1");
}

TEST(Anyplace, ProjectionIsMetresEastAndNorth) {
    // One degree of latitude is R·π/180 ≈ 111 195 m; a degree of longitude shrinks by cos(lat).
    const Point north = project(41.0, -80.0, 40.0, -80.0);
    EXPECT_NEAR(north.x, 0.0, 1e-9);
    EXPECT_NEAR(north.y, 111195.08, 0.1);
    const Point east = project(40.0, -79.999, 40.0, -80.0);
    EXPECT_NEAR(east.x, 111.19508 * std::cos(40.0 * M_PI / 180.0), 1e-3);
    EXPECT_NEAR(east.y, 0.0, 1e-9);
}

TEST(Anyplace, RealHotelLogParsesCleanly) {
    const std::string path = std::string(LOCUS_DATA_DIR) + "/anyplace/hotelpitt/0/rss-log";
    std::ifstream in(path);
    if (!in) GTEST_SKIP() << "Anyplace sample not found at " << path << " (../shared/data absent)";
    std::stringstream ss;
    ss << in.rdbuf();
    const auto d = parse_anyplace(ss.str());
    EXPECT_TRUE(d.errors.empty());
    EXPECT_EQ(d.lines.size(), 9904u);  // wc -l of the file: no comment or bad line in it
}

}  // namespace
}  // namespace survey_sources_test
