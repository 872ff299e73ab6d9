// A plan keeps its floor's rooms and POIs in step, against the real server: a PUT creates,
// adopts, renames and deletes them in its own transaction; a refused plan changes none; a
// room or POI the plan keeps is changed only through the plan; DELETE plan lets them go as
// ordinary ones; localize answers the plan's room.
#include <gtest/gtest.h>

#include <map>

#include "hierarchy.hpp"
#include "plan_geojson.hpp"
#include "server_process.hpp"

namespace server_plan_rooms_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using locus::testing::feature;
using locus::testing::point;
using nlohmann::json;

json rect(double x0, double y0, double x1, double y1) { return locus::testing::rect_polygon(x0, y0, x1, y1); }

// A vector, not a json: `{feature}` into a json is an array of one for g++ but a copy of the
// feature for clang++ 14 (nlohmann-json's FAQ, "Brace initialization yields arrays").
json collection(std::vector<json> features) { return {{"type", "FeatureCollection"}, {"features", std::move(features)}}; }

// An L-shaped lab (10 × 4 plus 4 × 6 above its west end), an office, a corridor without a
// name, stairs and an elevator.
json office_plan(const std::string& lab_name = "Lab") {
    return collection({feature("space", locus::testing::polygon({{0, 0}, {10, 0}, {10, 4}, {4, 4}, {4, 10}, {0, 10}, {0, 0}}),
                               {{"name", lab_name}, {"tags", {"Dr. Rossi"}}}),
                       feature("space", rect(10, 0, 16, 4), {{"name", "Office"}}),
                       feature("space", rect(16, 0, 30, 4), {{"kind", "corridor"}}),
                       feature("connector", point(28, 2), {{"id", "s1"}, {"kind", "stairs"}}),
                       feature("connector", point(20, 2), {{"id", "l1"}, {"kind", "elevator"}, {"name", "Main lift"}})});
}

struct PlanRooms : ::testing::Test {
    ServerProcess s;
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    std::string floor = std::to_string(h.floor);
    std::string plan = "/v1/floors/" + floor + "/plan";

    // The floor's rooms (or POIs) by name.
    std::map<std::string, json> listed(const char* kind) {
        std::map<std::string, json> out;
        const auto page = body_of(s.get("/v1/floors/" + floor + "/" + kind + "?limit=1000"));
        for (const auto& r : page.at("items"))
            out[r.at("name").get<std::string>()] = r;
        return out;
    }
    static double area(const json& room) {
        double a = 0;
        for (const auto& r : room.at("rects"))
            a += (r.at("xmax").get<double>() - r.at("xmin").get<double>()) * (r.at("ymax").get<double>() - r.at("ymin").get<double>());
        return a;
    }
    std::int64_t post_room(const std::string& name, double x0, double y0, double x1, double y1) {
        return body_of(s.post("/v1/floors/" + floor + "/rooms",
                              {{"name", name}, {"rects", {{{"xmin", x0}, {"ymin", y0}, {"xmax", x1}, {"ymax", y1}}}}}),
                       201)
            .at("id")
            .get<std::int64_t>();
    }
};

// The properties of the plan's features, by feature kind and name (or connector id).
std::map<std::string, json> props_of(const json& plan) {
    std::map<std::string, json> out;
    for (const auto& f : plan.at("features")) {
        const auto& p = f.at("properties");
        std::string key = p.at("feature").get<std::string>() + ":";
        key += p.at("feature") == "connector" ? p.at("id").get<std::string>() : p.value("name", std::string());
        out[key] = p;
    }
    return out;
}

TEST_F(PlanRooms, APutCreatesTheRoomsAndPoisAndTheStoredPlanNamesThem) {
    const auto put = body_of(s.put(plan, office_plan()));
    const auto rooms = listed("rooms");
    ASSERT_EQ(rooms.size(), 2u);  // the unnamed corridor keeps none
    EXPECT_DOUBLE_EQ(area(rooms.at("Lab")), 64.0);
    EXPECT_EQ(rooms.at("Lab").at("rects").size(), 2u);
    EXPECT_DOUBLE_EQ(area(rooms.at("Office")), 24.0);

    const auto pois = listed("pois");
    ASSERT_EQ(pois.size(), 2u);
    EXPECT_EQ(pois.at("Stairs s1").at("kind"), "stairs");
    EXPECT_DOUBLE_EQ(pois.at("Stairs s1").at("x").get<double>(), 28.0);
    EXPECT_EQ(pois.at("Main lift").at("kind"), "elevator");
    EXPECT_DOUBLE_EQ(pois.at("Main lift").at("x").get<double>(), 20.0);

    // The answer and GET carry the ids; what GET gives can be PUT again unchanged.
    const auto props = props_of(put);
    EXPECT_EQ(props.at("space:Lab").at("room_id"), rooms.at("Lab").at("id"));
    EXPECT_EQ(props.at("space:Office").at("room_id"), rooms.at("Office").at("id"));
    EXPECT_TRUE(props.at("space:").at("room_id").is_null());
    EXPECT_EQ(props.at("connector:s1").at("poi_id"), pois.at("Stairs s1").at("id"));
    EXPECT_EQ(props.at("connector:l1").at("poi_id"), pois.at("Main lift").at("id"));
    const auto got = body_of(s.get(plan));
    EXPECT_EQ(got.at("features"), put.at("features"));
    EXPECT_EQ(body_of(s.put(plan, got)).at("features"), put.at("features"));
    EXPECT_EQ(listed("rooms"), rooms);
    EXPECT_EQ(listed("pois"), pois);
}

TEST_F(PlanRooms, ASecondPutRenamesKeepsIdsAndDeletesWhatItNoLongerHas) {
    const auto first = props_of(body_of(s.put(plan, office_plan())));
    const auto lab_id = first.at("space:Lab").at("room_id");
    const auto office_id = first.at("space:Office").at("room_id");

    // The lab renamed (by its room_id, as a client PUTting back what it read does), the
    // office and the stairs dropped, the lift moved.
    json next = body_of(s.get(plan));
    json kept = json::array();
    for (auto f : next.at("features")) {
        auto& p = f.at("properties");
        if (p.value("name", json()) == "Office" || p.value("id", json()) == "s1") continue;
        if (p.value("name", json()) == "Lab") p["name"] = "Robotics lab";
        if (p.value("id", json()) == "l1") f["geometry"]["coordinates"] = {22.0, 2.0};
        kept.push_back(f);
    }
    next["features"] = kept;
    const auto second = props_of(body_of(s.put(plan, next)));
    EXPECT_EQ(second.at("space:Robotics lab").at("room_id"), lab_id);

    const auto rooms = listed("rooms");
    ASSERT_EQ(rooms.size(), 1u);
    EXPECT_EQ(rooms.at("Robotics lab").at("id"), lab_id);
    EXPECT_EQ(s.get("/v1/rooms/" + office_id.dump()).status, 404);
    const auto pois = listed("pois");
    ASSERT_EQ(pois.size(), 1u);
    EXPECT_DOUBLE_EQ(pois.at("Main lift").at("x").get<double>(), 22.0);
    EXPECT_EQ(pois.at("Main lift").at("id"), first.at("connector:l1").at("poi_id"));

    // Without room_ids a space is kept by the floor's room of its name: the same ids again.
    json by_name = office_plan("Robotics lab");
    const auto third = props_of(body_of(s.put(plan, by_name)));
    EXPECT_EQ(third.at("space:Robotics lab").at("room_id"), lab_id);
    EXPECT_NE(third.at("space:Office").at("room_id"), office_id);  // deleted above: a new one
    EXPECT_EQ(third.at("connector:l1").at("poi_id"), first.at("connector:l1").at("poi_id"));
}

TEST_F(PlanRooms, APlanDrawnOverExistingRoomsAdoptsThemByName) {
    const auto lab = post_room("Lab", 0, 0, 5, 5);
    const auto other = post_room("Kitchen", 40, 0, 45, 5);  // not in the plan: left alone
    const auto lift = body_of(s.post("/v1/floors/" + floor + "/pois", {{"name", "Main lift"}, {"x", 1.0}, {"y", 1.0}}), 201).at("id");
    const auto props = props_of(body_of(s.put(plan, office_plan())));
    EXPECT_EQ(props.at("space:Lab").at("room_id"), lab);
    EXPECT_EQ(props.at("connector:l1").at("poi_id"), lift);
    const auto rooms = listed("rooms");
    ASSERT_EQ(rooms.size(), 3u);
    EXPECT_DOUBLE_EQ(area(rooms.at("Lab")), 64.0);  // its rects now follow the space
    EXPECT_EQ(rooms.at("Kitchen").at("id"), other);
    EXPECT_EQ(listed("pois").at("Main lift").at("kind"), "elevator");
    // The kitchen is no plan's: it stays editable, and a later plan without the lab deletes
    // only what the plan kept.
    EXPECT_EQ(s.patch("/v1/rooms/" + std::to_string(other), {{"name", "Tea kitchen"}}).status, 200);
    const auto office_only = s.put(plan, collection({feature("space", rect(10, 0, 16, 4), {{"name", "Office"}})}));
    ASSERT_EQ(office_only.status, 200) << office_only.body;
    EXPECT_EQ(s.get("/v1/rooms/" + std::to_string(lab)).status, 404);
    EXPECT_EQ(s.get("/v1/rooms/" + std::to_string(other)).status, 200);
}

TEST_F(PlanRooms, SpacesOfOneNameKeepOneRoom) {
    const auto props = props_of(body_of(s.put(plan, collection({feature("space", rect(0, 0, 4, 4), {{"name", "Hall"}}),
                                                                   feature("space", rect(10, 0, 12, 4), {{"name", "Hall"}})}))));
    const auto rooms = listed("rooms");
    ASSERT_EQ(rooms.size(), 1u);
    EXPECT_DOUBLE_EQ(area(rooms.at("Hall")), 24.0);
    EXPECT_EQ(props.at("space:Hall").at("room_id"), rooms.at("Hall").at("id"));

    // A space without a name joins the room its room_id gives, under the room's name; with
    // no named space keeping that room, the room keeps its own name and takes the space's shape.
    const auto store = post_room("Store", 40, 0, 41, 1);
    const auto put = body_of(s.put(plan, collection({feature("space", rect(0, 0, 4, 4), {{"name", "Hall"}}),
                                                     feature("space", rect(10, 0, 12, 4), {{"room_id", rooms.at("Hall").at("id")}}),
                                                     feature("space", rect(20, 0, 23, 4), {{"room_id", store}})})));
    ASSERT_EQ(put.at("features").size(), 3u);
    EXPECT_EQ(put.at("features")[1].at("properties").at("room_id"), rooms.at("Hall").at("id"));
    EXPECT_EQ(put.at("features")[2].at("properties").at("room_id"), store);
    const auto after = listed("rooms");
    ASSERT_EQ(after.size(), 2u);
    EXPECT_DOUBLE_EQ(area(after.at("Hall")), 24.0);
    EXPECT_DOUBLE_EQ(area(after.at("Store")), 12.0);
    EXPECT_EQ(s.patch("/v1/rooms/" + std::to_string(store), {{"name", "Shop"}}).status, 409);  // kept now
}

TEST_F(PlanRooms, ARefusedPlanChangesNoRoomOrPoi) {
    const auto lonely = post_room("Lonely", 50, 0, 55, 5);
    ASSERT_EQ(s.put(plan, office_plan()).status, 200);
    const auto rooms = listed("rooms");
    const auto pois = listed("pois");
    const auto before = body_of(s.get(plan));

    auto with_lab_props = [&](json extra) {
        json p = office_plan();
        for (const auto& [k, v] : extra.items()) p["features"][0]["properties"][k] = v;
        return p;
    };
    const auto other = locus::testing::make_hierarchy(s, "Elsewhere");
    const auto elsewhere = body_of(s.post("/v1/floors/" + std::to_string(other.floor) + "/rooms",
                                          {{"name", "Far"}, {"rects", {{{"xmin", 0}, {"ymin", 0}, {"xmax", 1}, {"ymax", 1}}}}}),
                                   201)
                               .at("id")
                               .get<std::int64_t>();
    struct Case {
        json plan;
        std::string message;
    };
    json self_crossing = office_plan("Lab 2");
    self_crossing["features"][1]["geometry"]["coordinates"][0] = {{10, 0}, {16, 4}, {16, 0}, {10, 4}, {10, 0}};
    json clash = office_plan();
    clash["features"][0]["properties"]["room_id"] = rooms.at("Lab").at("id");
    clash["features"][1]["properties"]["room_id"] = rooms.at("Lab").at("id");
    json unnamed = office_plan();
    unnamed["features"][2]["properties"]["room_id"] = elsewhere;
    json bad_poi = office_plan();
    bad_poi["features"][3]["properties"]["poi_id"] = 987654;
    json taken = office_plan();
    taken["features"][1]["properties"]["room_id"] = lonely;  // renaming it to "Office" would clash
    taken["features"][1]["properties"]["name"] = "Lonely 2";
    json taken_name = office_plan();
    taken_name["features"][0]["properties"]["room_id"] = rooms.at("Office").at("id");  // "Office" → "Lab"…
    taken_name["features"][1]["properties"]["name"] = "Lonely";  // …and the office space takes a hand-made room's name
    taken_name["features"][1]["properties"]["room_id"] = rooms.at("Lab").at("id");
    json long_names = office_plan();  // two connectors of one 196-byte name: "… (l1)" would pass 200
    long_names["features"][3]["properties"]["name"] = std::string(196, 'n');
    long_names["features"][4]["properties"]["name"] = std::string(196, 'n');
    const std::vector<Case> cases = {
        {long_names, "): its POI's name would be 201 bytes long: POI names are at most 200"},
        {with_lab_props({{"room_id", elsewhere}}),
         "features[0] (space 'Lab'): room_id " + std::to_string(elsewhere) + " is not a room of floor " + floor},
        {with_lab_props({{"room_id", 99999}}), "features[0] (space 'Lab'): room_id 99999 is not a room of floor " + floor},
        {self_crossing, "spaces[1] 'Office'"},
        {clash, "features[1] (space 'Office'): room_id " + rooms.at("Lab").at("id").dump() + " is also kept by the space named 'Lab'"},
        {unnamed, "features[2] (space): room_id " + std::to_string(elsewhere) + " is not a room of floor " + floor},
        {bad_poi, "features[3] (connector 's1'): poi_id 987654 is not a POI of floor " + floor},
        {taken_name, "features[1] (space 'Lonely'): room " + std::to_string(lonely) + " of floor " + floor + " is already named 'Lonely'"},
    };
    for (const auto& c : cases) {
        const auto r = s.put(plan, c.plan);
        EXPECT_EQ(r.status, 422) << c.message << ": " << r.raw;
        EXPECT_EQ(r.body.value("/error/code"_json_pointer, json()), "invalid_plan") << r.raw;
        EXPECT_NE(r.raw.find(c.message), std::string::npos) << c.message << " not in " << r.raw;
        EXPECT_EQ(listed("rooms"), rooms) << c.message;
        EXPECT_EQ(listed("pois"), pois) << c.message;
        EXPECT_EQ(body_of(s.get(plan)), before) << c.message;
    }
    // A hand-made room taken over by room_id is fine once no one else holds the name.
    const auto ok = props_of(body_of(s.put(plan, taken)));
    EXPECT_EQ(ok.at("space:Lonely 2").at("room_id"), lonely);
    EXPECT_EQ(listed("rooms").count("Office"), 0u);  // the office's old room was the plan's: gone
}

TEST_F(PlanRooms, AKeptRoomOrPoiIsChangedOnlyThroughThePlan) {
    const auto props = props_of(body_of(s.put(plan, office_plan())));
    const auto room = "/v1/rooms/" + props.at("space:Lab").at("room_id").dump();
    const auto poi = "/v1/pois/" + props.at("connector:l1").at("poi_id").dump();
    for (const auto& r : {s.patch(room, {{"name", "Renamed"}}), s.del(room), s.patch(poi, {{"x", 3.0}}), s.del(poi)}) {
        EXPECT_EQ(r.status, 409) << r.raw;
        EXPECT_EQ(r.body.value("/error/code"_json_pointer, json()), "kept_by_plan") << r.raw;
        EXPECT_NE(r.raw.find("PUT /v1/floors/" + floor + "/plan"), std::string::npos) << r.raw;
    }
    const auto patched = s.patch(room, {{"name", "Renamed"}});
    EXPECT_NE(patched.raw.find("is kept by space 'Lab' of floor " + floor + "'s plan"), std::string::npos) << patched.raw;
    EXPECT_NE(s.del(poi).raw.find("is kept by connector 'Main lift'"), std::string::npos);
    EXPECT_EQ(listed("rooms").count("Lab"), 1u);
    // New rooms by hand stay allowed.
    post_room("Store", 40, 0, 42, 2);

    // DELETE plan lets them go as ordinary rooms and POIs: all there, all editable.
    ASSERT_EQ(s.del(plan).status, 204);
    EXPECT_EQ(listed("rooms").size(), 3u);
    EXPECT_EQ(listed("pois").size(), 2u);
    EXPECT_EQ(s.patch(room, {{"name", "Lab"}}).status, 200);
    EXPECT_EQ(s.patch(poi, {{"x", 3.0}}).status, 200);
    // A later plan takes them back by name.
    const auto again = props_of(body_of(s.put(plan, office_plan())));
    EXPECT_EQ("/v1/rooms/" + again.at("space:Lab").at("room_id").dump(), room);
    EXPECT_EQ("/v1/pois/" + again.at("connector:l1").at("poi_id").dump(), poi);
    EXPECT_EQ(s.patch(room, {{"name", "Renamed"}}).status, 409);

    // Deleting the floor deletes the plan and everything it kept, as before.
    ASSERT_EQ(s.del("/v1/floors/" + floor).status, 204);
    EXPECT_EQ(s.get(room).status, 404);
    EXPECT_EQ(s.get(poi).status, 404);
}

TEST_F(PlanRooms, LocalizeAnswersThePlansRoom) {
    json rps = {{"name", "one"},
                {"rps",
                 {{{"name", "in the lab"}, {"x", 2.0}, {"y", 8.0}, {"scans", 5},
                   {"measurements", {{{"type", "wifi"}, {"bssid", "aa:00:00:00:00:01"}, {"mean", -40.0}, {"variance", 4.0}, {"count", 5}}}}}}}};
    const auto rm = s.post("/v1/floors/" + floor + "/radiomaps/import", rps);
    ASSERT_EQ(rm.status, 201) << rm.raw;
    const auto localize = "/v1/radiomaps/" + rm.body.at("id").dump() + "/localize";
    const json scan = {{"algorithm", "nn"}, {"scans", json::array({json::array({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -41}}})})}};
    EXPECT_TRUE(body_of(s.post(localize, scan)).value("room", json()).is_null());  // no rooms yet

    ASSERT_EQ(s.put(plan, office_plan()).status, 200);
    EXPECT_EQ(body_of(s.post(localize, scan)).at("room").at("name"), "Lab");
    ASSERT_EQ(s.put(plan, office_plan("Robotics lab")).status, 200);
    EXPECT_EQ(body_of(s.post(localize, scan)).at("room").at("name"), "Robotics lab");
}

}  // namespace
}  // namespace server_plan_rooms_test
