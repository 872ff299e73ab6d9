// Aggregating raw scans and combining aggregates of one AP (shared/src/radio_map.cpp): what a
// scan upload stores, so it must equal merging the pieces one after another.
#include <gtest/gtest.h>

#include "locus/radio_map.hpp"

namespace radio_map_test {
namespace {

using namespace locus;

TEST(RadioMap, AggregateScansKeepsFirstSeenOrderPerTypeAndBssid) {
    const std::vector<Scan> scans = {{{"wifi", "b", -60}, {"wifi", "a", -50}, {"ble", "a", -70}},
                                     {{"wifi", "a", -54}}};
    const auto ms = aggregate_scans(scans);
    ASSERT_EQ(ms.size(), 3u);
    EXPECT_EQ(ms[0].bssid, "b");
    EXPECT_EQ(ms[1].bssid, "a");
    EXPECT_EQ(ms[1].type, "wifi");
    EXPECT_EQ(ms[1].stats.count, 2);
    EXPECT_DOUBLE_EQ(ms[1].stats.mean, -52.0);
    EXPECT_DOUBLE_EQ(ms[1].stats.variance, 4.0);
    EXPECT_EQ(ms[2].type, "ble");
}

TEST(RadioMap, CombiningAggregatesEqualsMergingThemInTurn) {
    std::vector<Measurement> ms = {{"wifi", "x", {-60.0, 2.0, 3}},
                                   {"ble", "x", {-80.0, 0.0, 1}},
                                   {"wifi", "x", {-64.0, 0.0, 1}},
                                   {"wifi", "y", {-50.0, 1.0, 2}}};
    RssStats expected{-60.0, 2.0, 3};
    expected.merge({-64.0, 0.0, 1});
    ASSERT_TRUE(combine_aggregates(ms));
    ASSERT_EQ(ms.size(), 3u);
    EXPECT_EQ(ms[0].bssid, "x");
    EXPECT_EQ(ms[0].type, "wifi");
    EXPECT_EQ(ms[0].stats.count, 4);
    EXPECT_DOUBLE_EQ(ms[0].stats.mean, expected.mean);
    EXPECT_DOUBLE_EQ(ms[0].stats.variance, expected.variance);
    EXPECT_EQ(ms[1].type, "ble");
    EXPECT_EQ(ms[2].bssid, "y");
}

TEST(RadioMap, CombiningRefusesCountsPastTheBoundAndNamesTheAp) {
    std::vector<Measurement> ms = {{"wifi", "big", {-60.0, 0.0, kMaxCount}}, {"wifi", "big", {-60.0, 0.0, 1}}};
    std::string overflow;
    EXPECT_FALSE(combine_aggregates(ms, &overflow));
    EXPECT_EQ(overflow, "big");
    std::vector<Measurement> fits = {{"wifi", "big", {-60.0, 0.0, kMaxCount - 1}}, {"wifi", "big", {-60.0, 0.0, 1}}};
    EXPECT_TRUE(combine_aggregates(fits));
    EXPECT_EQ(fits[0].stats.count, kMaxCount);
}

// One normal form, made once: from text a Bssid is normalised; what the store hands back is
// taken as written.
TEST(RadioMap, ABssidIsAlwaysInItsNormalForm) {
    EXPECT_EQ(Bssid(" AA-BB-CC-DD-EE-0F\t").str(), "aa:bb:cc:dd:ee:0f");
    EXPECT_EQ(Bssid("AA:BB:CC:DD:EE:0F").str(), "aa:bb:cc:dd:ee:0f");
    EXPECT_EQ(Bssid("Beacon-1").str(), "beacon-1");  // not a MAC: dashes stay
    EXPECT_EQ(Bssid("aa-bb-cc-dd-ee-fg").str(), "aa-bb-cc-dd-ee-fg");  // not hex
    EXPECT_EQ(Bssid("AA-BB-CC-DD-EE-0F"), Bssid("aa:bb:cc:dd:ee:0f"));
    EXPECT_TRUE(Bssid("b") > Bssid("A"));  // ordered by the normal form
    Reading r;
    r.bssid = std::string("  X ");  // the edge: text becomes a Bssid
    EXPECT_EQ(r.bssid.str(), "x");
    EXPECT_EQ(Bssid::stored("already:normal").str(), "already:normal");
    EXPECT_TRUE(Bssid().empty());
}

}  // namespace
}  // namespace radio_map_test
