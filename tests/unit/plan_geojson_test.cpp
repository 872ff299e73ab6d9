// The floor plan's GeoJSON codec (geojson/): what the server stores, the client reads and the
// CLI writes must survive the trip unchanged, and a bad document names its feature.
#include "locus/plan/geojson.hpp"

#include <gtest/gtest.h>

#include "plan_fixture.hpp"

namespace plan_geojson_test {
namespace {

using namespace locus;
using namespace locus::plan;
using namespace plan_fixture;
using nlohmann::json;

Plan every_feature_kind() {
    Plan p = two_rooms();
    p.spaces[0].tags = {"Dr. Rossi", "Müller"};
    p.spaces[0].kind = "office";
    p.spaces[1].room_id = 42;
    p.spaces[1].shape.holes.push_back(rect(12, 2, 13, 3));
    p.doors.push_back(door_between({10, 1}, {10, 2}, "wide"));
    auto c = connector("S1", ConnectorKind::elevator, {15, 5}, {{7, "E"}});
    c.seconds_per_level = 20;
    c.step_free = true;
    c.name = "Lift";
    p.connectors.push_back(c);
    return p;
}

TEST(PlanGeoJson, EveryFeatureKindSurvivesTheRoundTrip) {
    const Plan p = every_feature_kind();
    const json doc = to_geojson(p);
    EXPECT_EQ(doc.at("type"), "FeatureCollection");
    // Through text too, as it travels.
    const Plan back = from_geojson(json::parse(doc.dump()));
    EXPECT_EQ(to_geojson(back), doc);
    ASSERT_EQ(back.spaces.size(), p.spaces.size());
    EXPECT_EQ(back.spaces[0].tags, p.spaces[0].tags);
    EXPECT_EQ(back.spaces[1].room_id, std::optional<std::int64_t>(42));
    EXPECT_EQ(back.spaces[1].shape.holes.size(), 1u);
    ASSERT_EQ(back.connectors.size(), 1u);
    EXPECT_EQ(back.connectors[0].seconds_per_level, std::optional<double>(20));
    EXPECT_EQ(back.connectors[0].links[0].floor_id, 7);
    EXPECT_EQ(back.doors.back().b.y, 2);
}

TEST(PlanGeoJson, WhatTheServerAddsBesideFeaturesIsAccepted) {
    json doc = to_geojson(every_feature_kind());
    doc["floor_id"] = 3;
    doc["version"] = 2;
    doc["updated_at"] = "2026-11-30T00:00:00Z";
    EXPECT_NO_THROW(from_geojson(doc));
    doc["colour"] = "red";
    EXPECT_THROW(from_geojson(doc), GeoJsonError);
}

TEST(PlanGeoJson, ABadFeatureIsNamedByItsIndexAndName) {
    json doc = to_geojson(every_feature_kind());
    doc["features"][1]["geometry"]["coordinates"][0].erase(4);  // open the second space's ring
    try {
        from_geojson(doc);
        FAIL() << "an open ring was read";
    } catch (const GeoJsonError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("features[1]"), std::string::npos) << what;
        EXPECT_NE(what.find("closed"), std::string::npos) << what;
    }
    json twice = to_geojson(every_feature_kind());
    twice["features"].push_back(twice["features"].back());
    EXPECT_THROW(from_geojson(twice), GeoJsonError);  // connector id used twice
}

}  // namespace
}  // namespace plan_geojson_test
