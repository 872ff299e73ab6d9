// Floor plans over HTTP against the real server: PUT a GeoJSON plan, read it back exactly,
// replace it, link two floors by their stairs, delete it; every malformed plan is refused with
// the offending feature named and nothing written.
#include <gtest/gtest.h>

#include "hierarchy.hpp"
#include "plan_geojson.hpp"
#include "server_process.hpp"

namespace server_plan_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

using locus::testing::line;
using locus::testing::point;
using locus::testing::polygon;
using locus::testing::feature;

// Two rooms side by side, a wall between them with a door, stairs in the corridor.
json two_rooms(json stairs_links = json::array()) {
    return {{"type", "FeatureCollection"},
            {"features",
             {feature("space", polygon({{0, 0}, {5, 0}, {5, 4}, {0, 4}, {0, 0}}), {{"name", "Lab 1"}, {"tags", {"Dr. Rossi"}}}),
              feature("space", polygon({{5, 0}, {10, 0}, {10, 4}, {5, 4}, {5, 0}}), {{"name", "Corridor"}, {"kind", "corridor"}}),
              feature("wall", line({{5, 0}, {5, 4}})),
              feature("door", point(5, 2), {{"name", "Lab 1 door"}}),
              feature("connector", point(9, 3), {{"id", "s1"}, {"kind", "stairs"}, {"links", stairs_links}})}}};
}

std::string plan_path(std::int64_t floor) { return "/v1/floors/" + std::to_string(floor) + "/plan"; }

TEST(ServerPlan, APlanReadsBackAsItWasPutAndEachPutReplacesIt) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    EXPECT_EQ(s.get(plan_path(h.floor)).status, 404);  // none yet

    const auto put = body_of(s.put(plan_path(h.floor), two_rooms()), 200);
    EXPECT_EQ(put.at("version"), 1);
    const auto got = body_of(s.get(plan_path(h.floor)), 200);
    EXPECT_EQ(got, put);
    ASSERT_EQ(got.at("features").size(), 5u);
    const auto& lab = got.at("features")[0];
    EXPECT_EQ(lab.at("properties").at("name"), "Lab 1");
    EXPECT_EQ(lab.at("properties").at("kind"), "room");
    EXPECT_EQ(lab.at("properties").at("tags"), json({"Dr. Rossi"}));
    EXPECT_EQ(lab.at("geometry").at("coordinates")[0].size(), 5u);
    EXPECT_EQ(got.at("features")[3].at("geometry").at("type"), "Point");  // a point door stays a point
    EXPECT_EQ(got.at("features")[4].at("properties").at("step_free"), false);

    // What GET gives can be PUT again as it is; the version counts the PUTs.
    const auto again = body_of(s.put(plan_path(h.floor), got), 200);
    EXPECT_EQ(again.at("version"), 2);
    EXPECT_EQ(again.at("features"), got.at("features"));

    // It survives a restart.
    s.stop();
    s.start();
    EXPECT_EQ(body_of(s.get(plan_path(h.floor)), 200).at("features"), got.at("features"));

    EXPECT_EQ(s.del(plan_path(h.floor)).status, 204);
    EXPECT_EQ(s.get(plan_path(h.floor)).status, 404);
    EXPECT_EQ(s.del(plan_path(h.floor)).status, 404);
}

TEST(ServerPlan, LinksNameRealConnectorsAndEachFloorAddsOrDropsItsOwnSide) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const auto upper = body_of(s.post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                                      {{"name", "Upper"}, {"level", 1}, {"width", 10.0}, {"height", 4.0}}),
                               201)
                           .at("id")
                           .get<std::int64_t>();
    // The first floor may name a floor that has no plan yet.
    ASSERT_EQ(s.put(plan_path(h.floor), two_rooms({{{"floor_id", upper}, {"connector", "s1"}}})).status, 200);
    // A link must name a connector the other floor's plan has.
    const auto typo = s.put(plan_path(upper), two_rooms({{{"floor_id", h.floor}, {"connector", "s2"}}}));
    EXPECT_EQ(typo.status, 422) << typo.raw;
    EXPECT_EQ(typo.body.at("error").at("code"), "invalid_plan");
    EXPECT_NE(typo.raw.find("that floor's plan does not have"), std::string::npos) << typo.raw;
    EXPECT_EQ(s.get(plan_path(upper)).status, 404);  // nothing written
    // Each floor states its own side: the pair is complete once both say it, and either may
    // drop it again on its own.
    EXPECT_EQ(s.put(plan_path(upper), two_rooms({{{"floor_id", h.floor}, {"connector", "s1"}}})).status, 200);
    EXPECT_EQ(s.put(plan_path(h.floor), two_rooms()).status, 200);
    EXPECT_EQ(s.put(plan_path(h.floor), two_rooms({{{"floor_id", upper}, {"connector", "s1"}}})).status, 200);
    // A floor of another map is not a floor this plan can reach.
    const auto other = locus::testing::make_hierarchy(s, "Elsewhere");
    const auto foreign = s.put(plan_path(upper), two_rooms({{{"floor_id", other.floor}, {"connector", "s1"}}}));
    EXPECT_EQ(foreign.status, 422);
    EXPECT_NE(foreign.raw.find("not a floor of this map"), std::string::npos) << foreign.raw;
}

TEST(ServerPlan, MalformedPlansAreRefusedNamingTheFeatureAndWriteNothing) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    const auto good = two_rooms();
    ASSERT_EQ(s.put(plan_path(h.floor), good).status, 200);
    const auto before = body_of(s.get(plan_path(h.floor)), 200);

    struct Case {
        const char* what;
        json plan;
        const char* message;  // part of the expected message
    };
    auto with = [&](std::size_t i, json f) {
        json p = good;
        p["features"][i] = std::move(f);
        return p;
    };
    const std::vector<Case> cases = {
        {"not GeoJSON", json{{"features", json::array()}}, "FeatureCollection"},
        {"open ring", with(0, feature("space", polygon({{0, 0}, {5, 0}, {5, 4}, {0, 4}}), {{"name", "Lab 1"}})), "closed"},
        {"too few points", with(0, feature("space", polygon({{0, 0}, {5, 0}, {0, 0}}), {{"name", "Lab 1"}})), "features[0] (space 'Lab 1')"},
        {"huge coordinate", with(2, feature("wall", line({{5, 0}, {5, 2e5}}))), "1e5"},
        {"not a number", with(2, feature("wall", {{"type", "LineString"}, {"coordinates", {{5, 0}, {"x", 4}}}})), "features[2]"},
        {"unknown feature", with(2, feature("window", line({{5, 0}, {5, 4}}))), "space, wall, door or connector"},
        {"wrong geometry", with(3, feature("door", polygon({{0, 0}, {1, 0}, {1, 1}, {0, 0}}))), "Point or LineString"},
        {"unknown connector kind", with(4, feature("connector", point(9, 3), {{"id", "s1"}, {"kind", "rope"}})), "stairs, elevator"},
        {"connector without id", with(4, feature("connector", point(9, 3), {{"kind", "stairs"}})), "'id'"},
        {"unknown property", with(2, feature("wall", line({{5, 0}, {5, 4}}), {{"colour", "red"}})), "unknown field"},
        {"link to nowhere", two_rooms({{{"floor_id", 999}, {"connector", "s1"}}}), "not a floor of this map"},
        {"link to itself", two_rooms({{{"floor_id", h.floor}, {"connector", "s1"}}}), "its own floor"},
        {"self-intersecting ring", with(0, feature("space", polygon({{0, 0}, {5, 4}, {5, 0}, {0, 4}, {0, 0}}), {{"name", "Lab 1"}})), "spaces[0] 'Lab 1'"},
        {"door on no wall", with(3, feature("door", point(2, 2), {{"name", "Nowhere"}})), "doors[0] 'Nowhere'"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.what);
        const auto r = s.put(plan_path(h.floor), c.plan);
        EXPECT_EQ(r.status, 422) << r.raw;
        EXPECT_NE(r.raw.find(c.message), std::string::npos) << r.raw;
    }
    auto two = good;
    two["features"].push_back(two["features"][4]);
    const auto twice = s.put(plan_path(h.floor), two);
    EXPECT_EQ(twice.status, 422);
    EXPECT_NE(twice.raw.find("used twice"), std::string::npos) << twice.raw;

    EXPECT_EQ(s.put(plan_path(h.floor), json::array()).status, 400);  // not an object
    EXPECT_EQ(s.put(plan_path(999), good).status, 404);
    EXPECT_EQ(s.get(plan_path(999)).status, 404);
    EXPECT_EQ(body_of(s.get(plan_path(h.floor)), 200), before);  // every refusal wrote nothing
}

TEST(ServerPlan, DeletingTheFloorDeletesItsPlan) {
    ServerProcess s;
    const auto h = locus::testing::make_hierarchy(s);
    ASSERT_EQ(s.put(plan_path(h.floor), two_rooms()).status, 200);
    ASSERT_EQ(s.del("/v1/floors/" + std::to_string(h.floor)).status, 204);
    EXPECT_EQ(s.get(plan_path(h.floor)).status, 404);
}

}  // namespace
}  // namespace server_plan_test
