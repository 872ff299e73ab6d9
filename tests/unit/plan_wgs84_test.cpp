// A plan document in RFC 7946 form and back (geojson/include/locus/plan/wgs84.hpp).
#include "locus/plan/wgs84.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "locus/plan/geojson.hpp"

namespace plan_wgs84_test {
namespace {

using locus::geo::FloorToEarth;
using locus::geo::Georeference;
using nlohmann::json;
namespace plan = locus::plan;

constexpr double kPi = 3.14159265358979323846;

// The IPIN 2023 venue's origin; +y to true north.
FloorToEarth nuremberg() { return FloorToEarth(Georeference{{49.46115, 11.11115}, {0, 0}, 0.0}); }

json square(bool clockwise) {
    json ring = clockwise ? json::parse("[[0,0],[0,10],[10,10],[10,0],[0,0]]") : json::parse("[[0,0],[10,0],[10,10],[0,10],[0,0]]");
    return {{"type", "FeatureCollection"},
            {"floor_id", 3},
            {"features",
             {{{"type", "Feature"}, {"geometry", {{"type", "Polygon"}, {"coordinates", {ring}}}}, {"properties", {{"feature", "space"}, {"name", "Hall"}}}},
              {{"type", "Feature"}, {"geometry", {{"type", "Point"}, {"coordinates", {10.0, 0.0}}}}, {"properties", {{"feature", "door"}}}}}}};
}

double ring_area(const json& ring) {
    double a = 0;
    for (std::size_t i = 0; i + 1 < ring.size(); ++i)
        a += ring[i][0].get<double>() * ring[i + 1][1].get<double>() - ring[i + 1][0].get<double>() * ring[i][1].get<double>();
    return a;
}

TEST(PlanWgs84, PositionsAreLongitudeLatitudeWithSevenDecimals) {
    const json out = plan::plan_to_wgs84(square(false), nuremberg());
    EXPECT_FALSE(out.contains("crs"));
    const json door = out["features"][1]["geometry"]["coordinates"];
    // 10 m east at 49.46115° N: the README of the IPIN data gives the east radius of curvature
    // there as 6,390,503 m × cos(lat).
    const double expected_lon = 11.11115 + 10.0 / (6390503.0 * std::cos(49.46115 * kPi / 180)) * 180 / kPi;
    EXPECT_NEAR(door[0].get<double>(), expected_lon, 2e-7);
    EXPECT_NEAR(door[1].get<double>(), 49.46115, 2e-7);
    const double scaled = door[0].get<double>() * 1e7;
    EXPECT_NEAR(scaled, std::round(scaled), 1e-3) << "at most 7 decimals";
    const json bbox = out["bbox"];
    ASSERT_EQ(bbox.size(), 4u);
    EXPECT_NEAR(bbox[0].get<double>(), 11.11115, 2e-7);
    EXPECT_NEAR(bbox[2].get<double>(), expected_lon, 2e-7);
    EXPECT_NEAR(bbox[3].get<double>(), 49.46115 + 10.0 / 6372360.0 * 180 / kPi, 2e-7);
}

TEST(PlanWgs84, RingsAreWoundByTheRightHandRule) {
    for (bool clockwise : {false, true}) {
        const json out = plan::plan_to_wgs84(square(clockwise), nuremberg());
        EXPECT_GT(ring_area(out["features"][0]["geometry"]["coordinates"][0]), 0) << "exterior counter-clockwise";
    }
}

TEST(PlanWgs84, ARoundTripComesBackWithinACentimetre) {
    const FloorToEarth earth(Georeference{{49.46115, 11.11115}, {50, 20}, 339.264});
    const json back = plan::plan_from_wgs84(plan::plan_to_wgs84(square(false), earth), earth);
    EXPECT_EQ(back["crs"], plan::kFloorMetresCrs);
    EXPECT_FALSE(back.contains("bbox"));
    const json door = back["features"][1]["geometry"]["coordinates"];
    EXPECT_NEAR(door[0].get<double>(), 10.0, 0.01);
    EXPECT_NEAR(door[1].get<double>(), 0.0, 0.01);
    EXPECT_NO_THROW(plan::from_geojson(back));
}

TEST(PlanWgs84, TheCrsMemberSaysTheForm) {
    EXPECT_EQ(plan::crs_of(json::object()), plan::DocumentCrs::floor_metres);
    EXPECT_EQ(plan::crs_of({{"crs", "locus:floor-metres"}}), plan::DocumentCrs::floor_metres);
    EXPECT_EQ(plan::crs_of({{"crs", {{"type", "name"}, {"properties", {{"name", "urn:ogc:def:crs:OGC:1.3:CRS84"}}}}}}),
              plan::DocumentCrs::wgs84);
    EXPECT_EQ(plan::crs_of({{"crs", "EPSG:3857"}}), plan::DocumentCrs::unknown);
    json wrong = square(false);
    wrong["crs"] = "EPSG:4326";
    EXPECT_THROW(plan::from_geojson(wrong), plan::GeoJsonError) << "floor metres only say locus:floor-metres";
}

TEST(PlanWgs84, PositionsOutOfRangeNameTheirFeature) {
    json doc = plan::plan_to_wgs84(square(false), nuremberg());
    doc["features"][1]["geometry"]["coordinates"] = {11.1, 95.0};
    try {
        plan::plan_from_wgs84(doc, nuremberg());
        FAIL() << "a latitude of 95 was taken";
    } catch (const plan::GeoJsonError& e) {
        EXPECT_NE(std::string(e.what()).find("features[1]"), std::string::npos) << e.what();
    }
    doc["features"][1]["geometry"]["coordinates"] = {"a", 1};
    EXPECT_THROW(plan::plan_from_wgs84(doc, nuremberg()), plan::GeoJsonError);
}

}  // namespace
}  // namespace plan_wgs84_test
