// The REST client's JSON shapes: request bodies as the server reads them, and answers read
// leniently, a missing, null or mistyped field keeping its default.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "locus/api/types.hpp"

namespace api_types_test {
namespace {

using namespace locus;
using nlohmann::json;

TEST(ApiTypes, ReadingsNameTheirTypeOnlyWhenNotWifi) {
    const Scan scan{{"wifi", "aa:bb", -50.0}, {"ble", "beacon", -70.5}};
    EXPECT_EQ(json(scan), json::parse(R"([{"bssid":"aa:bb","rss":-50.0},{"bssid":"beacon","rss":-70.5,"type":"ble"}])"));
}

TEST(ApiTypes, AnUploadSendsScansOrElseMeasurements) {
    api::ScanUpload u;
    u.measurements = {{"ble", "x", {-60.0, 2.5, 4}}};
    EXPECT_EQ(json(u), json::parse(
                           R"({"measurements":[{"type":"ble","bssid":"x","mean":-60.0,"variance":2.5,"count":4}]})"));
    u.upload_id = "u1";
    u.scans = {{{"wifi", "a", -40.0}}, {}};
    EXPECT_EQ(json(u), json::parse(R"({"upload_id":"u1","scans":[[{"bssid":"a","rss":-40.0}],[]]})"));
    EXPECT_EQ(json(api::ScanUpload{}), json::parse(R"({"measurements":[]})"));
}

TEST(ApiTypes, ALocalizeRequestNamesOnlyWhatWasAsked) {
    api::LocalizeRequest r;
    r.scans = {{{"wifi", "a", -40.0}}};
    EXPECT_EQ(json(r), json::parse(R"({"scans":[[{"bssid":"a","rss":-40.0}]]})"));
    r.algorithm = "knn";
    r.options = {{"k", 5}};
    EXPECT_EQ(json(r), json::parse(R"({"scans":[[{"bssid":"a","rss":-40.0}]],"algorithm":"knn","options":{"k":5}})"));
}

TEST(ApiTypes, NullMissingOrMistypedFieldsKeepTheirDefaults) {
    const auto map = json::parse(R"({"id":4,"name":"HQ","description":null})").get<api::MapInfo>();
    EXPECT_EQ(map.id, 4);
    EXPECT_EQ(map.name, "HQ");
    EXPECT_EQ(map.description, "");
    const auto floor = json::parse(R"({"id":"7","name":3,"level":-1,"width":12.5,"height":null})").get<api::FloorInfo>();
    EXPECT_EQ(floor.id, 0);
    EXPECT_EQ(floor.name, "");
    EXPECT_EQ(floor.level, -1);
    EXPECT_DOUBLE_EQ(floor.width, 12.5);
    EXPECT_DOUBLE_EQ(floor.height, 0.0);
    EXPECT_EQ(floor.building_id, 0);
    const auto m = json::parse(R"({"bssid":"aa","mean":-61.5,"count":3,"type":null})").get<Measurement>();
    EXPECT_EQ(m.type, "wifi");
    EXPECT_EQ(m.bssid, "aa");
    EXPECT_DOUBLE_EQ(m.stats.mean, -61.5);
    EXPECT_DOUBLE_EQ(m.stats.variance, 0.0);
    EXPECT_EQ(m.stats.count, 3);
}

TEST(ApiTypes, RoomsPoisAndRpsReadIntoTheCoreTypes) {
    const auto room = json::parse(R"({"id":2,"floor_id":9,"name":"lab",
        "rects":[{"xmin":0,"ymin":1,"xmax":4,"ymax":5},{"xmin":4,"ymax":2},"junk"]})").get<api::RoomInfo>();
    EXPECT_EQ(room.floor_id, 9);
    const Room& core = room;
    EXPECT_EQ(core.id, 2);
    EXPECT_EQ(core.name, "lab");
    ASSERT_EQ(core.rects.size(), 3u);
    EXPECT_DOUBLE_EQ(core.rects[0].ymin, 1.0);
    EXPECT_DOUBLE_EQ(core.rects[0].xmax, 4.0);
    EXPECT_DOUBLE_EQ(core.rects[1].xmin, 4.0);
    EXPECT_DOUBLE_EQ(core.rects[1].xmax, 0.0);
    EXPECT_DOUBLE_EQ(core.rects[2].xmax, 0.0);  // not an object: every side defaulted
    EXPECT_TRUE(core.contains({2.0, 3.0}));
    EXPECT_EQ(json(core.rects[0]), json::parse(R"({"xmin":0.0,"ymin":1.0,"xmax":4.0,"ymax":5.0})"));

    const auto poi = json::parse(R"({"id":3,"floor_id":9,"name":"door","kind":"exit","x":1.5,"y":2.5})").get<api::PoiInfo>();
    EXPECT_EQ(poi.floor_id, 9);
    EXPECT_EQ(poi.kind, "exit");
    EXPECT_DOUBLE_EQ(poi.at.x, 1.5);
    EXPECT_DOUBLE_EQ(poi.at.y, 2.5);

    const auto rp = json::parse(R"({"id":5,"radiomap_id":6,"name":"r","x":1,"y":2,"scans":10,
        "measurements":[{"type":"ble","bssid":"b","mean":-70,"variance":1.5,"count":10},{"bssid":"c"}]})")
                        .get<api::RpInfo>();
    EXPECT_EQ(rp.radiomap_id, 6);
    const ReferencePoint& point = rp;
    EXPECT_EQ(point.id, 5);
    EXPECT_DOUBLE_EQ(point.at.y, 2.0);
    EXPECT_EQ(point.scans, 10);
    ASSERT_EQ(point.measurements.size(), 2u);
    EXPECT_EQ(point.measurements[0].type, "ble");
    EXPECT_DOUBLE_EQ(point.measurements[0].stats.variance, 1.5);
    EXPECT_EQ(point.measurements[1].type, "wifi");
    EXPECT_EQ(point.measurements[1].stats.count, 0);
    EXPECT_TRUE(json::parse(R"({"measurements":null})").get<api::RpInfo>().measurements.empty());
}

TEST(ApiTypes, ALocalizeAnswerReadsIntoTheMatchersResult) {
    const json answer = json::parse(R"({"x":1.5,"y":2.5,"floor_id":3,"building_id":4,"room":{"id":8,"name":"lab"},
        "rps":[11,12],"score":0.25,"matched_aps":6,"algorithm":"wknn",
        "candidates":[{"rp_id":11,"x":1,"y":2,"score":0.25,"floor_id":3,"building_id":4,"matched_aps":6},
                      {"rp_id":12,"x":2,"y":3,"score":0.5,"floor_id":3,"building_id":4,"matched_aps":5}]})");
    const auto r = answer.get<api::LocalizeResult>();
    EXPECT_DOUBLE_EQ(r.at.x, 1.5);
    EXPECT_DOUBLE_EQ(r.at.y, 2.5);
    EXPECT_EQ(r.floor_id, 3);
    EXPECT_EQ(r.building_id, 4);
    EXPECT_EQ(r.room, "lab");
    EXPECT_EQ(r.rp_ids, (std::vector<long long>{11, 12}));
    EXPECT_DOUBLE_EQ(r.score, 0.25);
    EXPECT_EQ(r.matched_aps, 6);
    EXPECT_EQ(r.algorithm, "wknn");
    ASSERT_EQ(r.candidates.size(), 2u);
    EXPECT_EQ(r.candidates[1].rp_id, 12);
    EXPECT_DOUBLE_EQ(r.candidates[1].at.y, 3.0);
    EXPECT_DOUBLE_EQ(r.candidates[1].score, 0.5);
    EXPECT_EQ(r.candidates[1].matched_aps, 5);
    EXPECT_EQ(r.raw, answer);
    EXPECT_FALSE(json::parse(R"({"x":1,"room":null})").get<api::LocalizeResult>().room);
}

}  // namespace
}  // namespace api_types_test
