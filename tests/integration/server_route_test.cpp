// Routes over HTTP against the real server: two floors joined by stairs and an elevator,
// from a room to a POI; step_free takes the elevator; avoid; a plan change reroutes at once;
// no route and every bad input answer 4xx naming what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <utility>
#include <map>
#include <set>

#include "hierarchy.hpp"
#include "plan_geojson.hpp"
#include "server_process.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_route_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

using locus::testing::point;
using locus::testing::feature;
json rect(double x0, double y0, double x1, double y1) { return locus::testing::rect_polygon(x0, y0, x1, y1); }

// A 30 m × 10 m floor: a corridor (y 0..4), a lab above its west end behind a wall with a
// door at x = 5 (or none), stairs at the east end and an elevator at the west end.
json floor_plan(std::int64_t other_floor, bool lab_door, std::int64_t lab_room = 0) {
    json lab_props = {{"name", "Lab"}};
    if (lab_room) lab_props["room_id"] = lab_room;
    json features = {feature("space", rect(0, 0, 30, 4), {{"name", "Corridor"}, {"kind", "corridor"}}),
                     feature("space", rect(0, 4, 10, 10), lab_props),
                     feature("wall", {{"type", "LineString"}, {"coordinates", {{0, 4}, {10, 4}}}}),
                     feature("connector", point(28, 2), {{"id", "stairs"}, {"kind", "stairs"}, {"links", {{{"floor_id", other_floor}, {"connector", "stairs"}}}}}),
                     feature("connector", point(1, 2), {{"id", "lift"}, {"kind", "elevator"}, {"links", {{{"floor_id", other_floor}, {"connector", "lift"}}}}})};
    if (lab_door) features.push_back(feature("door", point(5, 4), {{"name", "Lab door"}}));
    return {{"type", "FeatureCollection"}, {"features", features}};
}

struct Building {
    locus::testing::Hierarchy h;
    std::int64_t upper = 0, lab_room = 0, poi = 0;
};

Building make_building(ServerProcess& s) {
    Building b;
    b.h = locus::testing::make_hierarchy(s);
    const auto floors = "/v1/buildings/" + std::to_string(b.h.building) + "/floors";
    b.upper = body_of(s.post(floors, {{"name", "Upper"}, {"level", 1}, {"width", 30.0}, {"height", 10.0}}), 201).at("id").get<std::int64_t>();
    b.lab_room = body_of(s.post("/v1/floors/" + std::to_string(b.h.floor) + "/rooms",
                                {{"name", "Lab"}, {"rects", {{{"xmin", 0}, {"ymin", 4}, {"xmax", 10}, {"ymax", 10}}}}}),
                         201)
                     .at("id")
                     .get<std::int64_t>();
    b.poi = body_of(s.post("/v1/floors/" + std::to_string(b.upper) + "/pois", {{"name", "Printer"}, {"x", 20.0}, {"y", 2.0}}), 201)
                .at("id")
                .get<std::int64_t>();
    EXPECT_EQ(s.put("/v1/floors/" + std::to_string(b.h.floor) + "/plan", floor_plan(b.upper, true, b.lab_room)).status, 200);
    EXPECT_EQ(s.put("/v1/floors/" + std::to_string(b.upper) + "/plan", floor_plan(b.h.floor, true)).status, 200);
    return b;
}

std::string route_path(const Building& b) { return "/v1/maps/" + std::to_string(b.h.map) + "/route"; }

TEST(ServerRoute, FromARoomUpTheStairsToAPoi) {
    ServerProcess s;
    const auto b = make_building(s);
    const auto r = body_of(s.post(route_path(b), {{"from", {{"room_id", b.lab_room}}}, {"to", {{"poi_id", b.poi}}}}), 200);
    // Lab centre (5, 7) → the door near (5, 4) → stairs (28, 2) → up → printer (20, 2): at
    // least the straight lines, and not much more than the way through the door.
    const double lower_bound = std::hypot(23.0, 5.0) + 8.0;
    EXPECT_GE(r.at("length_m").get<double>(), lower_bound - 0.01);
    EXPECT_LE(r.at("length_m").get<double>(), (3.0 + std::hypot(23.0, 2.0) + 8.0) * 1.05);
    ASSERT_EQ(r.at("legs").size(), 2u);
    EXPECT_EQ(r.at("legs")[0].at("floor_id"), b.h.floor);
    EXPECT_EQ(r.at("legs")[1].at("floor_id"), b.upper);
    ASSERT_EQ(r.at("transfers").size(), 1u);
    EXPECT_EQ(r.at("transfers")[0].at("kind"), "stairs");
    EXPECT_EQ(r.at("geojson").at("features").size(), 2u);
    bool up_the_stairs = false;
    for (const auto& step : r.at("steps")) up_the_stairs |= step.at("text").get<std::string>().find("stairs up to level 1") != std::string::npos;
    EXPECT_TRUE(up_the_stairs) << r.at("steps").dump();
    EXPECT_GT(r.at("time_s").get<double>(), r.at("length_m").get<double>() / 1.3);  // walking plus the stairs

    // Without steps: the elevator at the west end.
    const auto lift = body_of(s.post(route_path(b), {{"from", {{"room_id", b.lab_room}}}, {"to", {{"poi_id", b.poi}}},
                                                     {"options", {{"step_free", true}}}}),
                              200);
    ASSERT_EQ(lift.at("transfers").size(), 1u);
    EXPECT_EQ(lift.at("transfers")[0].at("kind"), "elevator");
}

TEST(ServerRoute, APlanChangeReroutesAndNoRouteSaysWhy) {
    ServerProcess s;
    const auto b = make_building(s);
    const json lab_to_corridor = {{"from", {{"room_id", b.lab_room}}}, {"to", {{"floor_id", b.h.floor}, {"x", 20.0}, {"y", 2.0}}}};
    ASSERT_EQ(s.post(route_path(b), lab_to_corridor).status, 200);
    // Avoiding the lab still lets a route start in it.
    EXPECT_EQ(s.post(route_path(b), {{"from", lab_to_corridor.at("from")}, {"to", lab_to_corridor.at("to")},
                                     {"options", {{"avoid", {b.lab_room}}}}})
                  .status,
              200);
    // The upper floor drops its side of the stairs and the lift: no way up any more.
    const json to_upper = {{"from", {{"room_id", b.lab_room}}}, {"to", {{"poi_id", b.poi}}}};
    ASSERT_EQ(s.post(route_path(b), to_upper).status, 200);
    json lone = floor_plan(b.h.floor, true);
    for (auto& f : lone["features"])
        if (f["properties"]["feature"] == "connector") f["properties"]["links"] = json::array();
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(b.upper) + "/plan", lone).status, 200);
    EXPECT_EQ(s.post(route_path(b), to_upper).status, 422);
    // The door walled up: the next route knows at once.
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(b.h.floor) + "/plan", floor_plan(b.upper, false, b.lab_room)).status, 200);
    const auto none = s.post(route_path(b), lab_to_corridor);
    EXPECT_EQ(none.status, 422) << none.raw;
    EXPECT_EQ(none.body.at("error").at("code"), "no_route");
    EXPECT_NE(none.raw.find("no walkable way"), std::string::npos) << none.raw;
}

// A map whose route graph would pass --max-route-graph-mb answers 422 route_graph_too_large,
// naming the flag, and is not built; other maps route as before, and the map itself once its
// plan shrinks. Two 30 m × 10 m floors: 2 × 4,800 cells of 0.25 m × (22 + 4 × 6) bytes, 0.4 MB;
// a 400 m × 10 m hall: 64,000 cells × 38 bytes, 2.3 MB; 100 m: 0.6 MB.
TEST(ServerRoute, AMapPastTheGraphBoundIsRefusedAndOthersRouteOn) {
    ServerProcess s{{"--max-route-graph-mb", "2"}};
    const auto b = make_building(s);
    const json in_lab = {{"from", {{"room_id", b.lab_room}}}, {"to", {{"poi_id", b.poi}}}};
    ASSERT_EQ(s.post(route_path(b), in_lab).status, 200);

    const auto big = locus::testing::make_hierarchy(s, "Campus");
    const auto hall = [](double length) {
        return json{{"type", "FeatureCollection"}, {"features", {feature("space", rect(0, 0, length, 10), {{"name", "Hall"}})}}};
    };
    ASSERT_EQ(s.patch("/v1/floors/" + std::to_string(big.floor), {{"width", 400.0}, {"height", 10.0}}).status, 200);
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(big.floor) + "/plan", hall(400)).status, 200);
    const std::string big_route = "/v1/maps/" + std::to_string(big.map) + "/route";
    const json along = {{"from", {{"floor_id", big.floor}, {"x", 1.0}, {"y", 5.0}}}, {"to", {{"floor_id", big.floor}, {"x", 90.0}, {"y", 5.0}}}};
    for (int i = 0; i < 2; ++i) {
        const auto refused = s.post(big_route, along);
        EXPECT_EQ(refused.status, 422) << refused.raw;
        EXPECT_EQ(refused.body.at("error").at("code"), "route_graph_too_large") << refused.raw;
        EXPECT_NE(refused.raw.find("--max-route-graph-mb"), std::string::npos) << refused.raw;
        EXPECT_NE(refused.raw.find("64000 cells"), std::string::npos) << refused.raw;
    }
    EXPECT_EQ(s.post(route_path(b), in_lab).status, 200);
    // Two phones on the big map: where one is from the other, without the walk.
    const auto a_track = locus::testing::open_track(s, {{"map_id", big.map}, {"label", "ann"}}),
               b_track = locus::testing::open_track(s, {{"map_id", big.map}, {"label", "bob"}});
    const double now = locus::testing::unix_now();
    for (const auto& [t, x] : {std::pair{a_track, 1.0}, std::pair{b_track, 90.0}}) {
        const json fixes = {{"fixes", {{{"t", now - 1}, {"floor_id", big.floor}, {"x", x}, {"y", 5.0}, {"accuracy_m", 1.5}}}}};
        ASSERT_EQ(locus::testing::track_call(s, "POST", t.path("/fixes"), {t.token}, fixes.dump()).status, 200);
    }
    const auto rel = locus::testing::track_call(s, "GET", a_track.path("/relative/" + std::to_string(b_track.id)), {a_track.token, b_track.token});
    ASSERT_EQ(rel.status, 200) << rel.raw;
    EXPECT_NEAR(rel.body.at("straight_distance_m").get<double>(), 89.0, 1e-9);
    EXPECT_FALSE(rel.body.contains("walking_distance_m"));
    EXPECT_NE(rel.body.value("walking_problem", "").find("--max-route-graph-mb"), std::string::npos) << rel.raw;
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(big.floor) + "/plan", hall(100)).status, 200);
    const auto routed = s.post(big_route, along);
    EXPECT_EQ(routed.status, 200) << routed.raw;
}

TEST(ServerRoute, ABadGraphBoundIsRefusedAtStart) {
    const std::string dir = locus::testing::make_temp_dir();
    for (const char* value : {"0", "-5", "x", "2000000"}) {
        // `timeout`: a server that wrongly started is stopped rather than hanging the test.
        const auto r = locus::testing::run_command(
            {"/usr/bin/timeout", "10", LOCUS_SERVER_BIN, "--db", dir + "/never.db", "--port", "0", "--max-route-graph-mb", value});
        EXPECT_NE(r.status, 0) << value;
        EXPECT_NE(r.status, 124) << value << ": the server started";
        EXPECT_NE(r.err.find("--max-route-graph-mb"), std::string::npos) << value << ": " << r.err;
    }
    std::filesystem::remove_all(dir);
}

TEST(ServerRoute, BadInputIsRefusedNamingWhat) {
    ServerProcess s;
    const auto b = make_building(s);
    const json here = {{"floor_id", b.h.floor}, {"x", 20.0}, {"y", 2.0}};
    struct Case {
        json body;
        int status;
        const char* message;
    };
    const auto other = locus::testing::make_hierarchy(s, "Elsewhere");
    const std::vector<Case> cases = {
        {{{"to", here}}, 422, "'from'"},
        {{{"from", here}, {"to", {{"floor_id", b.h.floor}, {"x", "a"}, {"y", 1}}}}, 422, "to.x"},
        {{{"from", here}, {"to", {{"floor_id", b.h.floor}, {"x", 1e6}, {"y", 1}}}}, 422, "to.x"},
        {{{"from", here}, {"to", {{"room_id", -3}}}}, 422, "to.room_id"},
        {{{"from", here}, {"to", {{"room_id", 999}}}}, 422, "'to': room 999 not found"},
        {{{"from", here}, {"to", {{"poi_id", 999}}}}, 422, "'to': poi 999 not found"},
        {{{"from", {{"floor_id", 999}, {"x", 1}, {"y", 1}}}, {"to", here}}, 422, "'from': floor 999 not found"},
        {{{"from", here}, {"to", {{"floor_id", other.floor}, {"x", 1}, {"y", 1}}}}, 422, "not in map"},
        {{{"from", here}, {"to", here}, {"options", {{"step_free", "yes"}}}}, 422, "step_free"},
        {{{"from", here}, {"to", here}, {"options", {{"avoid", {"lab"}}}}}, 422, "avoid"},
        {{{"from", here}, {"to", here}, {"options", {{"speed", 2}}}}, 422, "unknown field"},
        {{{"from", here}, {"to", {{"floor_id", b.h.floor}, {"x", 20.0}, {"y", 9.0}}}}, 422, "'to' is more than 2 m"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.body.dump());
        const auto r = s.post(route_path(b), c.body);
        EXPECT_EQ(r.status, c.status) << r.raw;
        EXPECT_NE(r.raw.find(c.message), std::string::npos) << r.raw;
    }
    EXPECT_EQ(s.post("/v1/maps/999/route", {{"from", here}, {"to", here}}).status, 404);
    EXPECT_EQ(s.post_raw(route_path(b), "[1]").status, 400);
}

// The id of the room called `name` on the demo map's floor at `level` (0 or 1).
std::int64_t demo_room(const ServerProcess& s, int level, const std::string& name) {
    const auto floors = body_of(s.get("/v1/buildings/1/floors")).at("items");
    for (const auto& f : floors) {
        if (f.at("level") != level) continue;
        const json rooms = body_of(s.get("/v1/floors/" + std::to_string(f.at("id").get<std::int64_t>()) + "/rooms"));
        for (const auto& r : rooms.at("items"))
            if (r.at("name") == name) return r.at("id").get<std::int64_t>();
    }
    ADD_FAILURE() << "the demo map has no room '" << name << "' at level " << level;
    return 0;
}

TEST(ServerRoute, TheDemoMapGoesUpstairsByTheStairsAndStepFreeByTheElevator) {
    ServerProcess s({"--demo"});
    // Both floors have a plan, its spaces named as the floor's rooms.
    for (const std::int64_t floor : {1, 2}) {
        const auto plan = body_of(s.get("/v1/floors/" + std::to_string(floor) + "/plan"));
        std::set<std::string> spaces, rooms;
        int connectors = 0;
        for (const auto& f : plan.at("features")) {
            if (f.at("properties").at("feature") == "space") spaces.insert(f.at("properties").at("name").get<std::string>());
            if (f.at("properties").at("feature") == "connector") ++connectors;
        }
        const json listed = body_of(s.get("/v1/floors/" + std::to_string(floor) + "/rooms"));
        for (const auto& r : listed.at("items")) rooms.insert(r.at("name").get<std::string>());
        EXPECT_EQ(spaces, rooms) << "floor " << floor;
        EXPECT_EQ(connectors, 2) << "floor " << floor;
    }

    const auto lab = demo_room(s, 0, "Lab"), server_room = demo_room(s, 1, "Server room");
    const json request = {{"from", {{"room_id", lab}}}, {"to", {{"room_id", server_room}}}};
    const auto by_stairs = body_of(s.post("/v1/maps/1/route", request));
    ASSERT_EQ(by_stairs.at("transfers").size(), 1u);
    EXPECT_EQ(by_stairs.at("transfers")[0].at("kind"), "stairs");
    EXPECT_EQ(by_stairs.at("transfers")[0].at("from_level"), 0);
    EXPECT_EQ(by_stairs.at("transfers")[0].at("to_level"), 1);
    ASSERT_EQ(by_stairs.at("legs").size(), 2u);
    EXPECT_EQ(by_stairs.at("legs")[0].at("level"), 0);
    EXPECT_EQ(by_stairs.at("legs")[1].at("level"), 1);
    bool says_stairs = false;
    for (const auto& step : by_stairs.at("steps")) says_stairs = says_stairs || step.at("text") == "Take the stairs up to level 1";
    EXPECT_TRUE(says_stairs) << by_stairs.at("steps").dump();

    json step_free = request;
    step_free["options"] = {{"step_free", true}};
    const auto by_lift = body_of(s.post("/v1/maps/1/route", step_free));
    ASSERT_EQ(by_lift.at("transfers").size(), 1u);
    EXPECT_EQ(by_lift.at("transfers")[0].at("kind"), "elevator");
    // The lift waits longer than the stairs take: the stairs were the quicker way.
    EXPECT_GT(by_lift.at("time_s").get<double>(), by_stairs.at("time_s").get<double>());
    // Each way leaves the ground floor where its connector stands on the plan.
    std::map<std::string, json> at;
    const json ground = body_of(s.get("/v1/floors/1/plan"));
    for (const auto& f : ground.at("features"))
        if (f.at("properties").at("feature") == "connector") at[f.at("properties").at("kind").get<std::string>()] = f.at("geometry").at("coordinates");
    auto near = [](const json& a, const json& b) { return std::hypot(a[0].get<double>() - b[0].get<double>(), a[1].get<double>() - b[1].get<double>()) < 0.5; };
    EXPECT_TRUE(near(by_stairs.at("legs")[0].at("path").back(), at.at("stairs"))) << by_stairs.at("legs")[0].dump();
    EXPECT_TRUE(near(by_lift.at("legs")[0].at("path").back(), at.at("elevator"))) << by_lift.at("legs")[0].dump();
}

}  // namespace
}  // namespace server_route_test
