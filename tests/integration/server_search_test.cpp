// The directory search over HTTP against the real server: a floor with a plan whose office is
// linked to an API room and tagged with its people, a café space, a nameless tagged space over
// a hall room, and POIs, plus a floor above. Accents, case, prefixes and typos are found and ranked; every
// hit's route_to is a `to` POST /route accepts and ends where the hit says; the index follows
// renames, deletes and plan edits; bad input answers 4xx naming what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "hierarchy.hpp"
#include "plan_geojson.hpp"
#include "server_process.hpp"

namespace server_search_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using locus::testing::feature;
using locus::testing::point;
using nlohmann::json;

json rect(double x0, double y0, double x1, double y1) { return locus::testing::rect_polygon(x0, y0, x1, y1); }

std::string encoded(const std::string& s) {
    std::string out;
    for (const unsigned char c : s) {
        if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
            out.push_back(static_cast<char>(c));
        } else {
            char buf[4];
            std::snprintf(buf, sizeof buf, "%%%02X", c);
            out += buf;
        }
    }
    return out;
}

// A 30 m × 20 m ground floor: a corridor along y 0..4; above it the office (linked to its API
// room), the café (a space) and the hall (an API room; its space has no name, only a tag), each
// with a door.
json ground_plan(std::int64_t office_room, const json& office_tags) {
    return {{"type", "FeatureCollection"},
            {"features",
             {feature("space", rect(0, 0, 30, 4), {{"name", "Corridor"}, {"kind", "corridor"}}),
              feature("space", rect(0, 4, 10, 10), {{"name", "Office 0.12"}, {"kind", "office"}, {"tags", office_tags}, {"room_id", office_room}}),
              feature("space", rect(10, 4, 20, 10), {{"name", "Café"}, {"kind", "cafeteria"}, {"tags", {"Espresso bar"}}}),
              feature("space", rect(20, 4, 30, 10), {{"kind", "hall"}, {"tags", {"Coat check"}}}),
              feature("wall", {{"type", "LineString"}, {"coordinates", {{0, 4}, {30, 4}}}}),
              feature("door", point(5, 4)),
              feature("door", point(15, 4)),
              feature("door", point(25, 4))}}};
}

struct Site {
    locus::testing::Hierarchy h;
    std::int64_t upper = 0, office = 0, hall = 0, printer = 0, toilets = 0, upstairs_printer = 0;
    std::string search(const std::string& q, const std::string& extra = "") const {
        return "/v1/maps/" + std::to_string(h.map) + "/search?q=" + encoded(q) + extra;
    }
};

std::int64_t id_of(const locus::testing::Response& r) { return body_of(r, 201).at("id").get<std::int64_t>(); }

Site make_site(ServerProcess& s) {
    Site site;
    site.h = locus::testing::make_hierarchy(s);
    const auto rooms = "/v1/floors/" + std::to_string(site.h.floor) + "/rooms";
    const auto pois = "/v1/floors/" + std::to_string(site.h.floor) + "/pois";
    site.office = id_of(s.post(rooms, {{"name", "Office 0.12"}, {"rects", {{{"xmin", 0}, {"ymin", 4}, {"xmax", 10}, {"ymax", 10}}}}}));
    site.hall = id_of(s.post(rooms, {{"name", "Müller Hall"}, {"rects", {{{"xmin", 20}, {"ymin", 4}, {"xmax", 30}, {"ymax", 10}}}}}));
    site.printer = id_of(s.post(pois, {{"name", "Printer"}, {"kind", "printer"}, {"x", 12.0}, {"y", 2.0}}));
    site.toilets = id_of(s.post(pois, {{"name", "Toilets"}, {"kind", "toilet"}, {"x", 28.0}, {"y", 2.0}}));
    site.upper = id_of(s.post("/v1/buildings/" + std::to_string(site.h.building) + "/floors",
                              {{"name", "First"}, {"level", 1}, {"width", 30.0}, {"height", 20.0}}));
    site.upstairs_printer = id_of(s.post("/v1/floors/" + std::to_string(site.upper) + "/pois",
                                         {{"name", "Colour printer"}, {"kind", "printer"}, {"x", 3.0}, {"y", 3.0}}));
    EXPECT_EQ(s.put("/v1/floors/" + std::to_string(site.h.floor) + "/plan", ground_plan(site.office, {"Dr. Rossi", "Anna Müller"})).status, 200);
    return site;
}

std::vector<std::string> names(const json& answer) {
    std::vector<std::string> out;
    for (const auto& h : answer.at("hits")) out.push_back(h.at("name").get<std::string>());
    return out;
}

TEST(ServerSearch, FindsAccentsCasePrefixesAndTyposWithWhereToGo) {
    ServerProcess s;
    const auto site = make_site(s);

    // The café: its name without the accent, any case, a prefix.
    for (const std::string q : {"cafe", "CAFÉ", "Caf", "  café  "}) {
        SCOPED_TRACE(q);
        const auto r = body_of(s.get(site.search(q)));
        ASSERT_EQ(r.at("hits").size(), 1u) << r.dump();
        const auto& hit = r.at("hits")[0];
        EXPECT_EQ(hit.at("name"), "Café");
        EXPECT_EQ(hit.at("category"), "cafeteria");
        EXPECT_EQ(hit.at("matched"), "name");
        EXPECT_EQ(hit.at("tags"), json({"Espresso bar"}));
        EXPECT_EQ(hit.at("floor_id"), site.h.floor);
        EXPECT_EQ(hit.at("level"), 0);
        EXPECT_EQ(hit.at("building_id"), site.h.building);
        EXPECT_DOUBLE_EQ(hit.at("x").get<double>(), 15.0);  // the space's middle
        EXPECT_DOUBLE_EQ(hit.at("y").get<double>(), 7.0);
        // A named space may be kept in step with a room of its own (docs/spec.md §2.4): then it is
        // that room, else a space reached by position.
        if (hit.at("kind") == "room") {
            EXPECT_EQ(hit.at("route_to"), json({{"room_id", hit.at("id")}}));
        } else {
            EXPECT_EQ(hit.at("kind"), "space");
            EXPECT_FALSE(hit.contains("id"));
            EXPECT_EQ(hit.at("route_to"), json({{"floor_id", site.h.floor}, {"x", 15.0}, {"y", 7.0}}));
        }
    }

    // A space that no room stands for, found by its tag: reached by a point inside it.
    auto coat = body_of(s.get(site.search("coat check")));
    ASSERT_EQ(coat.at("hits").size(), 1u) << coat.dump();
    EXPECT_EQ(coat.at("hits")[0],
              json({{"kind", "space"}, {"name", ""}, {"category", "hall"}, {"matched", "tag"}, {"tag", "Coat check"},
                    {"tags", {"Coat check"}}, {"floor_id", site.h.floor}, {"level", 0}, {"building_id", site.h.building},
                    {"x", 25.0}, {"y", 7.0}, {"score", 1.3}, {"route_to", {{"floor_id", site.h.floor}, {"x", 25.0}, {"y", 7.0}}}}));
    EXPECT_EQ(body_of(s.get(site.search("  café  "))).at("query"), "café");  // trimmed

    // One typo in the space's kind; a typo in a person's name, found in the linked room's tag.
    auto r = body_of(s.get(site.search("cafeterja")));
    ASSERT_EQ(names(r), std::vector<std::string>{"Café"});
    EXPECT_EQ(r.at("hits")[0].at("matched"), "category");
    r = body_of(s.get(site.search("dr rosi")));
    ASSERT_EQ(names(r), std::vector<std::string>{"Office 0.12"});
    const auto& office = r.at("hits")[0];
    EXPECT_EQ(office.at("kind"), "room");
    EXPECT_EQ(office.at("id"), site.office);
    EXPECT_EQ(office.at("matched"), "tag");
    EXPECT_EQ(office.at("tag"), "Dr. Rossi");
    EXPECT_EQ(office.at("tags"), json({"Dr. Rossi", "Anna Müller"}));
    EXPECT_EQ(office.at("category"), "office");
    EXPECT_DOUBLE_EQ(office.at("x").get<double>(), 5.0);  // the room's centre, as /route takes it
    EXPECT_DOUBLE_EQ(office.at("y").get<double>(), 7.0);
    EXPECT_EQ(office.at("route_to"), json({{"room_id", site.office}}));
    EXPECT_TRUE(body_of(s.get(site.search("dr rozzi"))).at("hits").empty());  // two typos

    // A whole name ranks first, then a name, then a tag; no more hits than the limit.
    EXPECT_EQ(names(body_of(s.get(site.search("muller")))), (std::vector<std::string>{"Müller Hall", "Office 0.12"}));
    EXPECT_EQ(names(body_of(s.get(site.search("printer")))), (std::vector<std::string>{"Printer", "Colour printer"}));
    r = body_of(s.get(site.search("printer", "&limit=1")));
    ASSERT_EQ(r.at("hits").size(), 1u);
    EXPECT_EQ(r.at("hits")[0].at("route_to"), json({{"poi_id", site.printer}}));
    EXPECT_GT(body_of(s.get(site.search("printer"))).at("hits")[0].at("score").get<double>(),
              body_of(s.get(site.search("printer"))).at("hits")[1].at("score").get<double>());
    r = body_of(s.get(site.search("colour")));
    ASSERT_EQ(r.at("hits").size(), 1u);
    EXPECT_EQ(r.at("hits")[0].at("level"), 1);
    EXPECT_EQ(r.at("hits")[0].at("floor_id"), site.upper);

    // A corridor with a name is listed; the hall room by its name before the space by its kind.
    EXPECT_EQ(names(body_of(s.get(site.search("corridor")))), std::vector<std::string>{"Corridor"});
    EXPECT_EQ(names(body_of(s.get(site.search("hall")))), (std::vector<std::string>{"Müller Hall", ""}));
}

TEST(ServerSearch, EveryRouteToIsATargetTheRouteEndpointTakes) {
    ServerProcess s;
    const auto site = make_site(s);
    const auto route = "/v1/maps/" + std::to_string(site.h.map) + "/route";
    int routed = 0;
    for (const std::string q : {"office", "cafe", "muller hall", "toilets", "printer", "corridor", "coat"}) {
        const json answer = body_of(s.get(site.search(q)));
        for (const auto& hit : answer.at("hits")) {
            if (hit.at("floor_id") != site.h.floor) continue;  // the upper floor has no plan
            SCOPED_TRACE(q + ": " + hit.dump());
            const auto r = body_of(s.post(route, {{"from", {{"poi_id", site.toilets}}}, {"to", hit.at("route_to")}}));
            // The route ends where the hit says the place is (snapped to the walkable grid).
            EXPECT_LT(std::hypot(r.at("to").at("x").get<double>() - hit.at("x").get<double>(),
                                 r.at("to").at("y").get<double>() - hit.at("y").get<double>()),
                      0.5);
            EXPECT_EQ(r.at("to").at("floor_id"), hit.at("floor_id"));
            ++routed;
        }
    }
    EXPECT_EQ(routed, 7);  // two rooms, two POIs, three spaces
}

TEST(ServerSearch, TheIndexFollowsWrites) {
    ServerProcess s;
    const auto site = make_site(s);
    ASSERT_EQ(names(body_of(s.get(site.search("muller hall")))).front(), "Müller Hall");

    // A renamed room is found under its new name only.
    body_of(s.patch("/v1/rooms/" + std::to_string(site.hall), {{"name", "Great Library"}}));
    EXPECT_EQ(names(body_of(s.get(site.search("library")))), std::vector<std::string>{"Great Library"});
    EXPECT_EQ(names(body_of(s.get(site.search("muller")))), std::vector<std::string>{"Office 0.12"});

    // A deleted POI is gone.
    ASSERT_EQ(s.del("/v1/pois/" + std::to_string(site.printer)).status, 204);
    EXPECT_EQ(names(body_of(s.get(site.search("printer")))), std::vector<std::string>{"Colour printer"});

    // New tags in the plan are found, the old ones no longer.
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(site.h.floor) + "/plan", ground_plan(site.office, {"Prof. Nakamura"})).status, 200);
    EXPECT_EQ(names(body_of(s.get(site.search("nakamura")))), std::vector<std::string>{"Office 0.12"});
    EXPECT_TRUE(body_of(s.get(site.search("rossi"))).at("hits").empty());

    // A deleted floor takes its POIs with it.
    ASSERT_EQ(s.del("/v1/floors/" + std::to_string(site.upper)).status, 204);
    EXPECT_TRUE(body_of(s.get(site.search("colour"))).at("hits").empty());

    // Scans do not touch the directory, and the search still answers after them.
    const auto rp = locus::testing::make_rp(s, site.h.radiomap, "rp1", 5, 2);
    ASSERT_GT(rp, 0);
    EXPECT_EQ(names(body_of(s.get(site.search("nakamura")))), std::vector<std::string>{"Office 0.12"});
}

TEST(ServerSearch, NeedsNoApiKey) {
    ServerProcess s({"--api-key", "sesame"});
    s.set_api_key("sesame");
    const auto site = make_site(s);
    s.set_api_key("");
    EXPECT_EQ(names(body_of(s.get(site.search("cafe")))), std::vector<std::string>{"Café"});
}

TEST(ServerSearch, BadInputIsRefusedNamingWhat) {
    ServerProcess s;
    const auto site = make_site(s);
    const auto base = "/v1/maps/" + std::to_string(site.h.map) + "/search";
    struct Case {
        std::string path;
        int status;
        const char* code;
        const char* message;
    };
    const std::vector<Case> cases = {
        {base, 400, "invalid_query", "'q' is required"},
        {base + "?limit=5", 400, "invalid_query", "'q' is required"},
        {base + "?q=", 400, "invalid_query", "'q' must not be empty"},
        {base + "?q=%20%20%09", 400, "invalid_query", "'q' must not be empty"},
        {base + "?q=" + std::string(201, 'a'), 400, "invalid_query", "at most 200"},
        {base + "?q=" + encoded(std::string(101, 'a') + std::string(100, ' ') + "é"), 400, "invalid_query", "at most 200"},
        {base + "?q=%FF%FE", 400, "invalid_query", "UTF-8"},
        {base + "?q=cafe&limit=0", 400, "invalid_query", "'limit' must be an integer in [1, 100]"},
        {base + "?q=cafe&limit=101", 400, "invalid_query", "'limit'"},
        {base + "?q=cafe&limit=x", 400, "invalid_query", "'limit'"},
        {base + "?q=cafe&limit=", 400, "invalid_query", "'limit'"},
        {"/v1/maps/999/search?q=cafe", 404, "not_found", "map 999 not found"},
        {"/v1/maps/abc/search?q=cafe", 404, "not_found", "no route"},
        {"/v1/maps/0/search?q=cafe", 404, "not_found", "map 0 not found"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.path);
        const auto r = s.get(c.path);
        EXPECT_EQ(r.status, c.status) << r.raw;
        ASSERT_TRUE(r.body.contains("error")) << r.raw;
        EXPECT_EQ(r.body.at("error").at("code"), c.code);
        EXPECT_NE(r.body.at("error").at("message").get<std::string>().find(c.message), std::string::npos) << r.raw;
    }
    // At the bounds: 200 characters (accents count once) and limit 100 are fine; a query of
    // punctuation only has no words and finds nothing.
    EXPECT_EQ(s.get(base + "?q=" + encoded(std::string(199, 'a') + "é")).status, 200);
    EXPECT_EQ(s.get(base + "?q=cafe&limit=100").status, 200);
    EXPECT_TRUE(body_of(s.get(base + "?q=" + encoded("?!"))).at("hits").empty());
}

}  // namespace
}  // namespace server_search_test
