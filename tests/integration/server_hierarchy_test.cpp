// The whole hierarchy over HTTP against the real server binary: create, read, list with
// pagination, patch, delete with cascade, restart.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_hierarchy_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

std::string id_path(const char* kind, const json& row) { return std::string("/v1/") + kind + "/" + std::to_string(row.at("id").get<long long>()); }

TEST(ServerHierarchy, HealthAnswersOk) {
    ServerProcess s;
    const auto r = s.get("/health");
    EXPECT_EQ(r.status, 200);
    EXPECT_EQ(r.body.at("status"), "ok");
}

TEST(ServerHierarchy, CreatesEveryKindAndReadsItBack) {
    ServerProcess s;
    auto map = s.post("/v1/maps", {{"name", "Campus"}, {"description", "test"}});
    ASSERT_EQ(map.status, 201) << map.raw;
    EXPECT_EQ(map.body.at("name"), "Campus");
    const auto map_id = map.body.at("id").get<long long>();

    auto building = s.post("/v1/maps/" + std::to_string(map_id) + "/buildings", {{"name", "A"}});
    ASSERT_EQ(building.status, 201) << building.raw;
    EXPECT_EQ(building.body.at("map_id"), map_id);

    auto floor = s.post(id_path("buildings", building.body) + "/floors",
                        {{"name", "Basement"}, {"level", -1}, {"width", 26.0}, {"height", 17.4}, {"north_offset_deg", 33.5}});
    ASSERT_EQ(floor.status, 201) << floor.raw;
    EXPECT_EQ(floor.body.at("level"), -1);
    EXPECT_DOUBLE_EQ(floor.body.at("north_offset_deg").get<double>(), 33.5);

    auto room = s.post(id_path("floors", floor.body) + "/rooms",
                       {{"name", "L-shaped"},
                        {"rects", {{{"xmin", 0}, {"ymin", 0}, {"xmax", 4}, {"ymax", 2}}, {{"xmin", 0}, {"ymin", 2}, {"xmax", 2}, {"ymax", 6}}}}});
    ASSERT_EQ(room.status, 201) << room.raw;
    ASSERT_EQ(room.body.at("rects").size(), 2u);
    EXPECT_DOUBLE_EQ(room.body.at("rects")[1].at("ymax").get<double>(), 6.0);

    auto poi = s.post(id_path("floors", floor.body) + "/pois", {{"name", "Exit 1"}, {"kind", "exit"}, {"x", 1.5}, {"y", 0.5}});
    ASSERT_EQ(poi.status, 201) << poi.raw;
    auto rm = s.post(id_path("floors", floor.body) + "/radiomaps", {{"name", "survey"}});
    ASSERT_EQ(rm.status, 201) << rm.raw;
    auto rp = s.post(id_path("radiomaps", rm.body) + "/rps", {{"name", "rp1"}, {"x", 1.0}, {"y", 2.0}});
    ASSERT_EQ(rp.status, 201) << rp.raw;
    EXPECT_EQ(rp.body.at("scans"), 0);

    for (auto [kind, row] : {std::pair{"maps", map.body}, {"buildings", building.body}, {"floors", floor.body},
                             {"rooms", room.body}, {"pois", poi.body}, {"radiomaps", rm.body}}) {
        const auto got = s.get(id_path(kind, row));
        EXPECT_EQ(got.status, 200) << kind;
        auto body = got.body;
        if (std::string(kind) == "radiomaps") {  // read with its matcher settings (none tuned yet)
            EXPECT_EQ(body.at("settings").at("source"), "built-in");
            EXPECT_FALSE(body.contains("tune"));
            body.erase("settings");
        }
        EXPECT_EQ(body, row) << kind;
    }
    const auto got_rp = s.get(id_path("rps", rp.body));
    EXPECT_EQ(got_rp.body.at("name"), "rp1");
    EXPECT_TRUE(got_rp.body.at("measurements").empty());
}

TEST(ServerHierarchy, ListsArePaginatedAndScopedToTheirParent) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const auto other = locus::testing::make_hierarchy(s, "Other");
    for (int i = 0; i < 7; ++i) locus::testing::make_rp(s, h.radiomap, "rp" + std::to_string(i), i, 0);
    locus::testing::make_rp(s, other.radiomap, "elsewhere", 0, 0);

    const std::string base = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/rps";
    const auto page1 = s.get(base + "?limit=3");
    ASSERT_EQ(page1.status, 200);
    EXPECT_EQ(page1.body.at("total"), 7);
    ASSERT_EQ(page1.body.at("items").size(), 3u);
    EXPECT_EQ(page1.body.at("items")[0].at("name"), "rp0");
    const auto page3 = s.get(base + "?limit=3&offset=6");
    ASSERT_EQ(page3.body.at("items").size(), 1u);
    EXPECT_EQ(page3.body.at("items")[0].at("name"), "rp6");
    EXPECT_TRUE(body_of(s.get(base + "?offset=100")).at("items").empty());
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 2);
}

TEST(ServerHierarchy, PatchChangesOnlyTheGivenFields) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const std::string floor = "/v1/floors/" + std::to_string(h.floor);
    const auto r = s.patch(floor, {{"north_offset_deg", -12.0}});
    ASSERT_EQ(r.status, 200) << r.raw;
    EXPECT_DOUBLE_EQ(r.body.at("north_offset_deg").get<double>(), -12.0);
    EXPECT_EQ(r.body.at("name"), "Ground");
    EXPECT_DOUBLE_EQ(r.body.at("width").get<double>(), 30.0);
    EXPECT_DOUBLE_EQ(body_of(s.get(floor)).at("north_offset_deg").get<double>(), -12.0);
}

TEST(ServerHierarchy, DeleteCascadesDownTheHierarchy) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const auto rp = locus::testing::make_rp(s, h.radiomap, "a", 1, 1);
    ASSERT_EQ(s.post("/v1/rps/" + std::to_string(rp) + "/scans", {{"scans", {{{{"bssid", "aa:bb:cc:dd:ee:ff"}, {"rss", -50}}}}}}).status, 200);
    const auto del = s.del("/v1/buildings/" + std::to_string(h.building));
    EXPECT_EQ(del.status, 204);
    EXPECT_EQ(s.get("/v1/buildings/" + std::to_string(h.building)).status, 404);
    EXPECT_EQ(s.get("/v1/floors/" + std::to_string(h.floor)).status, 404);
    EXPECT_EQ(s.get("/v1/radiomaps/" + std::to_string(h.radiomap)).status, 404);
    EXPECT_EQ(s.get("/v1/rps/" + std::to_string(rp)).status, 404);
    EXPECT_EQ(s.get("/v1/maps/" + std::to_string(h.map)).status, 200);
    EXPECT_EQ(s.del("/v1/buildings/" + std::to_string(h.building)).status, 404);
}

TEST(ServerHierarchy, EverythingIsFoundAgainAfterARestart) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const auto rp = locus::testing::make_rp(s, h.radiomap, "a", 3, 4);
    ASSERT_EQ(s.post("/v1/rps/" + std::to_string(rp) + "/scans",
                     {{"upload_id", "u1"}, {"scans", {{{{"bssid", "AA:BB:CC:DD:EE:01"}, {"rss", -60}}}, {{{"bssid", "aa:bb:cc:dd:ee:01"}, {"rss", -64}}}}}})
                  .status,
              200);
    const auto before = body_of(s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/export"));
    EXPECT_EQ(s.stop(), 0) << "SIGTERM must end the server cleanly";
    s.start();
    const auto after = body_of(s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/export"));
    EXPECT_EQ(before, after);
    EXPECT_EQ(body_of(s.get("/v1/maps/" + std::to_string(h.map))).at("name"), "HQ");
    // The upload id is remembered across the restart too.
    const auto again = s.post("/v1/rps/" + std::to_string(rp) + "/scans",
                              {{"upload_id", "u1"}, {"scans", {{{{"bssid", "aa:bb:cc:dd:ee:01"}, {"rss", -10}}}}}});
    EXPECT_EQ(again.status, 200);
    EXPECT_FALSE(again.body.at("applied").get<bool>());
}

TEST(ServerHierarchy, CommittedWritesSurviveKill9) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    for (int i = 0; i < 20; ++i) locus::testing::make_rp(s, h.radiomap, "rp" + std::to_string(i), i, i);
    s.kill9();
    s.start();
    EXPECT_EQ(body_of(s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/rps")).at("total"), 20);
}

TEST(ServerHierarchy, StartsWithTheDemoMapWhenAsked) {
    ServerProcess s({"--demo"});
    const auto maps = s.get("/v1/maps");
    ASSERT_EQ(maps.body.at("total"), 1);
    const auto map_id = maps.body.at("items")[0].at("id").get<long long>();
    const auto buildings = body_of(s.get("/v1/maps/" + std::to_string(map_id) + "/buildings"));
    ASSERT_EQ(buildings.at("total"), 1);
    const auto floors = body_of(s.get("/v1/buildings/" + std::to_string(buildings.at("items")[0].at("id").get<long long>()) + "/floors"));
    ASSERT_EQ(floors.at("total"), 2);
    const auto floor_id = floors.at("items")[0].at("id").get<long long>();
    EXPECT_GE(body_of(s.get("/v1/floors/" + std::to_string(floor_id) + "/rooms")).at("total").get<int>(), 2);
    EXPECT_GE(body_of(s.get("/v1/floors/" + std::to_string(floor_id) + "/pois")).at("total").get<int>(), 1);
    const auto rms = body_of(s.get("/v1/floors/" + std::to_string(floor_id) + "/radiomaps"));
    ASSERT_EQ(rms.at("total"), 1);
    EXPECT_GE(body_of(s.get("/v1/radiomaps/" + std::to_string(rms.at("items")[0].at("id").get<long long>()) + "/rps")).at("total").get<int>(), 12);
    // A restart with --demo on a non-empty database adds nothing.
    s.stop();
    s.start();
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 1);
}

TEST(ServerHierarchy, AccessLogHasOneStructuredLinePerRequest) {
    ServerProcess s;
    s.get("/v1/maps/12345");
    // The server logs a request after its answer is sent, so the line may trail the answer.
    const std::string line = R"("method":"GET","path":"/v1/maps/12345","remote":"127.0.0.1","status":404)";
    std::string log = s.log();
    for (int i = 0; i < 100 && log.find(line) == std::string::npos; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        log = s.log();
    }
    EXPECT_NE(log.find(line), std::string::npos) << log;
    EXPECT_NE(log.find(R"("us":)"), std::string::npos);
}

}  // namespace
}  // namespace server_hierarchy_test
