// Where am I, in words (docs/api.md): every position the server answers carries its room and
// the POIs within 1.5 m, nearest first. A localize answer, a posted fix's answer, a track's
// latest fix, a thin client's fused fixes and /positions, each against the real server; a
// room or POI written afterwards is in the next answer (the floors' cache follows the writes).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_places_test {
namespace {

using locus::testing::body_of;
using locus::testing::open_track;
using locus::testing::ServerProcess;
using locus::testing::Track;
using locus::testing::track_call;
using locus::testing::unix_now;
using nlohmann::json;

json m(const std::string& bssid, double mean) {
    return {{"type", "wifi"}, {"bssid", bssid}, {"mean", mean}, {"variance", 4.0}, {"count", 10}};
}

// A room (the west wing, x 0–6), two POIs near (2, 5) and one 3 m off; a radio map of two RPs,
// one at (2, 5), one at (18, 5).
struct Places : ::testing::Test {
    ServerProcess s{{"--quiet"}};
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    std::int64_t room = 0, desk = 0, exit = 0, far = 0, rm = 0;
    std::string floor_path;
    void SetUp() override {
        floor_path = "/v1/floors/" + std::to_string(h.floor);
        room = body_of(s.post(floor_path + "/rooms", {{"name", "West wing"}, {"rects", {{{"xmin", 0}, {"ymin", 0}, {"xmax", 6}, {"ymax", 10}}}}}), 201)
                   .at("id")
                   .get<std::int64_t>();
        desk = body_of(s.post(floor_path + "/pois", {{"name", "Front desk"}, {"kind", "desk"}, {"x", 2.0}, {"y", 6.0}}), 201).at("id").get<std::int64_t>();
        exit = body_of(s.post(floor_path + "/pois", {{"name", "Exit"}, {"kind", "exit"}, {"x", 2.5}, {"y", 5.0}}), 201).at("id").get<std::int64_t>();
        far = body_of(s.post(floor_path + "/pois", {{"name", "Lift"}, {"kind", "lift"}, {"x", 5.0}, {"y", 5.0}}), 201).at("id").get<std::int64_t>();
        const json corridor = {{"name", "corridor"},
                               {"rps",
                                {{{"name", "west"}, {"x", 2.0}, {"y", 5.0}, {"scans", 10}, {"measurements", {m("aa:00:00:00:00:01", -40), m("aa:00:00:00:00:02", -70)}}},
                                 {{"name", "east"}, {"x", 18.0}, {"y", 5.0}, {"scans", 10}, {"measurements", {m("aa:00:00:00:00:01", -70), m("aa:00:00:00:00:02", -40)}}}}}};
        rm = body_of(s.post(floor_path + "/radiomaps/import", corridor), 201).at("id").get<std::int64_t>();
    }
    // What (2, 5) should say: the west wing; the exit 0.5 m off, then the desk 1 m off.
    void expect_west(const json& where) const {
        ASSERT_TRUE(where.contains("room") && where.contains("nearby")) << where.dump();
        EXPECT_EQ(where["room"], (json{{"id", room}, {"name", "West wing"}}));
        ASSERT_EQ(where["nearby"].size(), 2u) << where.dump();
        EXPECT_EQ(where["nearby"][0], (json{{"poi_id", exit}, {"name", "Exit"}, {"kind", "exit"}, {"distance_m", 0.5}}));
        EXPECT_EQ(where["nearby"][1]["poi_id"], desk);
        EXPECT_DOUBLE_EQ(where["nearby"][1]["distance_m"].get<double>(), 1.0);
    }
};

json west_scan() {
    return {{"algorithm", "nn"}, {"scans", json::array({json::array({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -41}}, {{"bssid", "aa:00:00:00:00:02"}, {"rss", -69}}})})}};
}

TEST_F(Places, ALocalizeAnswerSaysItsRoomAndThePoisNearIt) {
    expect_west(body_of(s.post("/v1/radiomaps/" + std::to_string(rm) + "/localize", west_scan())));
    expect_west(body_of(s.post("/v1/maps/" + std::to_string(h.map) + "/localize", west_scan())));
    // At (18, 5): no room, nothing near; "nearby" is there, empty.
    json east = west_scan();
    east["scans"][0][0]["rss"] = -70;
    east["scans"][0][1]["rss"] = -40;
    const json a = body_of(s.post("/v1/radiomaps/" + std::to_string(rm) + "/localize", east));
    EXPECT_EQ(a["room"], nullptr);
    EXPECT_EQ(a["nearby"], json::array());
}

TEST_F(Places, ATracksFixesSayTheirRoomAndThePoisNearThem) {
    const Track t = open_track(s, {{"map_id", h.map}});
    const double t0 = std::floor(unix_now()) - 50;
    const json fix = {{"t", t0}, {"floor_id", h.floor}, {"x", 2.0}, {"y", 5.0}, {"accuracy_m", 2.0}};
    const json posted = body_of(track_call(s, "POST", "/v1/tracks/" + std::to_string(t.id) + "/fixes", {t.token}, json{{"fixes", {fix}}}.dump()));
    expect_west(posted["latest"]);
    expect_west(body_of(track_call(s, "GET", "/v1/tracks/" + std::to_string(t.id), {t.token}))["latest"]);
    const json positions = body_of(s.get("/v1/maps/" + std::to_string(h.map) + "/positions"));
    ASSERT_EQ(positions["positions"].size(), 1u) << positions.dump();
    expect_west(positions["positions"][0]["fix"]);
    // A thin client's fused fixes: a step east from there, 1 m (the exit 1.5 m off, the desk
    // √2 m, the lift 2 m: out).
    const json steps = {{"steps", {{{"t", t0 + 1}, {"length_m", 1.0}, {"heading_deg", 90.0}}}}};
    const json fused = body_of(track_call(s, "POST", "/v1/tracks/" + std::to_string(t.id) + "/steps", {t.token}, steps.dump()));
    ASSERT_EQ(fused["fused"].size(), 1u) << fused.dump();
    const json& f = fused["fused"][0];
    EXPECT_EQ(f["room"]["id"], room);
    for (const auto& n : f["nearby"]) {
        const double d = std::hypot(f["x"].get<double>() - (n["poi_id"] == exit ? 2.5 : n["poi_id"] == desk ? 2.0 : 5.0),
                                    f["y"].get<double>() - (n["poi_id"] == desk ? 6.0 : 5.0));
        EXPECT_NEAR(n["distance_m"].get<double>(), d, 1e-9) << n.dump();
        EXPECT_LE(d, 1.5);
    }
}

TEST_F(Places, ARoomOrPoiWrittenLaterIsInTheNextAnswer) {
    const std::string path = "/v1/radiomaps/" + std::to_string(rm) + "/localize";
    expect_west(body_of(s.post(path, west_scan())));  // read once: the floor's places are cached now
    body_of(s.del("/v1/pois/" + std::to_string(exit)), 204);
    const json after_delete = body_of(s.post(path, west_scan()));
    ASSERT_EQ(after_delete["nearby"].size(), 1u) << after_delete.dump();
    EXPECT_EQ(after_delete["nearby"][0]["poi_id"], desk);
    const auto kiosk = body_of(s.post(floor_path + "/pois", {{"name", "Kiosk"}, {"x", 2.0}, {"y", 5.0}}), 201).at("id").get<std::int64_t>();
    const json after_create = body_of(s.post(path, west_scan()));
    ASSERT_EQ(after_create["nearby"].size(), 2u) << after_create.dump();
    EXPECT_EQ(after_create["nearby"][0], (json{{"poi_id", kiosk}, {"name", "Kiosk"}, {"kind", ""}, {"distance_m", 0.0}}));
    body_of(s.patch("/v1/rooms/" + std::to_string(room), {{"name", "Reception"}}));
    EXPECT_EQ(body_of(s.post(path, west_scan()))["room"]["name"], "Reception");
}

}  // namespace
}  // namespace server_places_test
