// Scan uploads over HTTP: exact Welford merging, idempotent upload ids, BSSID normalisation,
// and the radio-map export/import round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_scans_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

json scans_of(const std::vector<double>& rss, const std::string& bssid) {
    json scans = json::array();
    for (double v : rss) scans.push_back(json::array({{{"type", "wifi"}, {"bssid", bssid}, {"rss", v}}}));
    return scans;
}

json measurement(const json& rp, const std::string& bssid) {
    for (const auto& m : rp.at("measurements"))
        if (m.at("bssid") == bssid) return m;
    return nullptr;
}

struct Fixture : ::testing::Test {
    ServerProcess s;
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    std::int64_t rp = locus::testing::make_rp(s, h.radiomap, "rp-1", 2.0, 3.0);
    std::string scans_path = "/v1/rps/" + std::to_string(rp) + "/scans";
};

TEST_F(Fixture, TwoUploadsMergeToTheStatisticsOfAllSamples) {
    const std::vector<double> first{-60, -61, -65, -58}, second{-70, -72, -66};
    auto r1 = s.post(scans_path, {{"upload_id", "a"}, {"scans", scans_of(first, "AA:BB:CC:00:00:01")}});
    ASSERT_EQ(r1.status, 200) << r1.raw;
    EXPECT_TRUE(r1.body.at("applied").get<bool>());
    auto r2 = s.post(scans_path, {{"upload_id", "b"}, {"scans", scans_of(second, "aa:bb:cc:00:00:01")}});
    ASSERT_EQ(r2.status, 200) << r2.raw;

    std::vector<double> all(first);
    all.insert(all.end(), second.begin(), second.end());
    double mean = 0;
    for (double v : all) mean += v;
    mean /= static_cast<double>(all.size());
    double var = 0;
    for (double v : all) var += (v - mean) * (v - mean);
    var /= static_cast<double>(all.size());

    const auto stored = body_of(s.get("/v1/rps/" + std::to_string(rp)));
    const auto m = measurement(stored, "aa:bb:cc:00:00:01");
    ASSERT_FALSE(m.is_null()) << stored.dump();
    EXPECT_EQ(m.at("count"), 7);
    EXPECT_NEAR(m.at("mean").get<double>(), mean, 1e-9);
    EXPECT_NEAR(m.at("variance").get<double>(), var, 1e-9);
    EXPECT_EQ(stored.at("scans"), 7);
    EXPECT_EQ(stored.at("measurements").size(), 1u) << "upper and lower case BSSIDs are one AP";
}

TEST_F(Fixture, ARepeatedUploadIdChangesNothing) {
    const json body = {{"upload_id", "file-1"}, {"scans", scans_of({-50, -52}, "aa:bb:cc:00:00:02")}};
    ASSERT_TRUE(body_of(s.post(scans_path, body)).at("applied").get<bool>());
    const auto before = body_of(s.get("/v1/rps/" + std::to_string(rp)));
    const auto again = s.post(scans_path, body);
    EXPECT_EQ(again.status, 200);
    EXPECT_FALSE(again.body.at("applied").get<bool>());
    EXPECT_EQ(body_of(s.get("/v1/rps/" + std::to_string(rp))), before);
}

TEST_F(Fixture, UploadsWithoutAnIdAlwaysMerge) {
    const json body = {{"scans", scans_of({-50}, "aa:bb:cc:00:00:03")}};
    s.post(scans_path, body);
    s.post(scans_path, body);
    EXPECT_EQ(measurement(body_of(s.get("/v1/rps/" + std::to_string(rp))), "aa:bb:cc:00:00:03").at("count"), 2);
}

TEST_F(Fixture, AggregatesMergeExactlyLikeRawScans) {
    // {-60, -62} as an aggregate, then {-64} raw: mean -62, population variance 8/3.
    auto r = s.post(scans_path, {{"measurements", {{{"type", "wifi"}, {"bssid", "aa:bb:cc:00:00:04"}, {"mean", -61.0}, {"variance", 1.0}, {"count", 2}}}}});
    ASSERT_EQ(r.status, 200) << r.raw;
    s.post(scans_path, {{"scans", scans_of({-64}, "aa:bb:cc:00:00:04")}});
    const auto m = measurement(body_of(s.get("/v1/rps/" + std::to_string(rp))), "aa:bb:cc:00:00:04");
    EXPECT_EQ(m.at("count"), 3);
    EXPECT_NEAR(m.at("mean").get<double>(), -62.0, 1e-12);
    EXPECT_NEAR(m.at("variance").get<double>(), 8.0 / 3.0, 1e-12);
}

TEST_F(Fixture, ApsSeenInSomeScansKeepTheirOwnCount) {
    json scans = json::array();
    for (int i = 0; i < 5; ++i) {
        json scan = json::array({{{"bssid", "aa:bb:cc:00:00:05"}, {"rss", -55 - i}}});
        if (i < 2) scan.push_back({{"bssid", "aa:bb:cc:00:00:06"}, {"rss", -90}});
        scans.push_back(scan);
    }
    s.post(scans_path, {{"scans", scans}});
    const auto stored = body_of(s.get("/v1/rps/" + std::to_string(rp)));
    EXPECT_EQ(stored.at("scans"), 5);
    EXPECT_EQ(measurement(stored, "aa:bb:cc:00:00:05").at("count"), 5);
    EXPECT_EQ(measurement(stored, "aa:bb:cc:00:00:06").at("count"), 2);
}

TEST_F(Fixture, ExportImportRoundTrip) {
    const auto rp2 = locus::testing::make_rp(s, h.radiomap, "rp-2", 9.5, 1.25);
    s.post(scans_path, {{"scans", scans_of({-40, -45, -47}, "aa:bb:cc:00:00:07")}});
    s.post("/v1/rps/" + std::to_string(rp2) + "/scans",
           {{"scans", json::array({json::array({{{"type", "ble"}, {"bssid", "beacon-7"}, {"rss", -77}}})})}});
    const auto exported = s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/export");
    ASSERT_EQ(exported.status, 200);
    EXPECT_EQ(exported.body.at("rps").size(), 2u);
    // Written out in pieces, the answer is byte for byte the document written as one value.
    EXPECT_EQ(exported.raw, exported.body.dump(-1, ' ', false, json::error_handler_t::replace));

    json doc = exported.body;
    doc["name"] = "copy";
    const auto imported = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", doc);
    ASSERT_EQ(imported.status, 201) << imported.raw;
    EXPECT_EQ(imported.body.at("rp_count"), 2);
    const auto again = body_of(s.get("/v1/radiomaps/" + std::to_string(imported.body.at("id").get<long long>()) + "/export"));
    EXPECT_EQ(again.at("rps"), exported.body.at("rps"));
    EXPECT_EQ(again.at("name"), "copy");

    // Importing under an existing name is a conflict and adds nothing.
    const auto dup = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", doc);
    EXPECT_EQ(dup.status, 409);
    EXPECT_EQ(body_of(s.get("/v1/floors/" + std::to_string(h.floor) + "/radiomaps")).at("total"), 2);
}

// More RPs than the export writes in one piece (256): the pieces join into the one document,
// and it imports back to the same RPs.
TEST_F(Fixture, ALargeExportIsOneDocumentThatImportsBack) {
    json rps = json::array();
    for (int i = 0; i < 600; ++i) {
        std::string name = std::to_string(i), bssid = "aa:bb:cc:00:01:";  // appended: GCC 12 misreads "p" + std::to_string(i) (-Wrestrict)
        name.insert(0, 1, 'p');
        bssid += std::to_string(10 + i % 90);
        rps.push_back({{"name", name}, {"x", 0.5 + (i % 19) * 0.5}, {"y", 0.25 + (i % 7) * 0.5}, {"scans", 2},
                       {"measurements", json::array({{{"type", "wifi"}, {"bssid", bssid}, {"mean", -40.0 - i % 50 - 1.0 / 3.0},
                                                      {"variance", 1.25}, {"count", 2}}})}});
    }
    json doc = {{"format", "locus-radiomap/1"}, {"name", "big"}, {"rps", rps}};
    const auto first = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", doc);
    ASSERT_EQ(first.status, 201) << first.raw;
    const auto exported = s.get("/v1/radiomaps/" + std::to_string(first.body.at("id").get<long long>()) + "/export");
    ASSERT_EQ(exported.status, 200) << exported.raw.substr(0, 200);
    EXPECT_EQ(exported.raw, exported.body.dump(-1, ' ', false, json::error_handler_t::replace));
    ASSERT_EQ(exported.body.at("rps").size(), 600u);
    for (std::size_t i = 0; i < 600; ++i) EXPECT_EQ(exported.body["rps"][i]["name"], rps[i]["name"]) << i;
    json again = exported.body;
    again["name"] = "big again";
    const auto second = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", again);
    ASSERT_EQ(second.status, 201) << second.raw;
    const auto reexported = body_of(s.get("/v1/radiomaps/" + std::to_string(second.body.at("id").get<long long>()) + "/export"));
    EXPECT_EQ(reexported.at("rps"), exported.body.at("rps"));
}

}  // namespace
}  // namespace server_scans_test
