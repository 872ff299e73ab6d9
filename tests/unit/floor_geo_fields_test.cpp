// A floor's "geo" object as the API takes and shows it (store::Field::group): validated into its
// five columns, folded back into one object (or null), refused whole when any member is wrong,
// and carried by a map bundle's floors.
#include <gtest/gtest.h>

#include "http/api_error.hpp"
#include "http/plans/floor_geo.hpp"
#include "http/crud/store_json.hpp"
#include "http/validation.hpp"
#include "store/kinds.hpp"

namespace floor_geo_fields_test {
namespace {

using nlohmann::json;
namespace http = locus::http;
namespace store = locus::store;

const store::Kind& floors() { return store::kind("floors"); }
const json kGeo = {{"lat", 49.46115181}, {"lon", 11.11114911}, {"x", 50.0}, {"y", 25.0}, {"bearing_deg", -20.736}};

std::string message_of(const json& body, bool create = false) {
    try {
        http::validated_fields(floors(), body, create);
    } catch (const http::ApiError& e) {
        return std::to_string(e.status) + " " + e.what();
    }
    return "ok";
}

TEST(FloorGeoFields, AnObjectBecomesFiveColumnsWithTheBearingInZeroTo360) {
    const auto v = http::validated_fields(floors(), {{"geo", kGeo}, {"elevation_m", -5.7}}, false);
    EXPECT_DOUBLE_EQ(v.get<double>("geo_lat"), 49.46115181);
    EXPECT_DOUBLE_EQ(v.get<double>("geo_lon"), 11.11114911);
    EXPECT_DOUBLE_EQ(v.get<double>("geo_x"), 50.0);
    EXPECT_DOUBLE_EQ(v.get<double>("geo_y"), 25.0);
    EXPECT_NEAR(v.get<double>("geo_bearing_deg"), 339.264, 1e-9);
    EXPECT_DOUBLE_EQ(v.get<double>("elevation_m"), -5.7);
    EXPECT_FALSE(v.has("geo"));
    // null clears every member; leaving it out touches none.
    const auto cleared = http::validated_fields(floors(), {{"geo", nullptr}}, false);
    for (const char* c : {"geo_lat", "geo_lon", "geo_x", "geo_y", "geo_bearing_deg"}) {
        ASSERT_TRUE(cleared.has(c)) << c;
        EXPECT_TRUE(std::holds_alternative<std::monostate>(cleared.values.at(c))) << c;
    }
    EXPECT_FALSE(http::validated_fields(floors(), {{"name", "F"}}, false).has("geo_lat"));
}

TEST(FloorGeoFields, AnyBadMemberRefusesTheWholeObjectNamingIt) {
    auto with = [](const char* key, json value) {
        json g = kGeo;
        if (value.is_discarded()) g.erase(key);
        else g[key] = std::move(value);
        return json{{"geo", g}};
    };
    EXPECT_NE(message_of(with("lat", 90.001)).find("'geo.lat'"), std::string::npos);
    EXPECT_NE(message_of(with("lon", -180.5)).find("'geo.lon'"), std::string::npos);
    EXPECT_NE(message_of(with("bearing_deg", 361)).find("'geo.bearing_deg'"), std::string::npos);
    EXPECT_NE(message_of(with("x", "1")).find("'geo.x'"), std::string::npos);
    EXPECT_NE(message_of(with("y", json(json::value_t::discarded))).find("missing field 'geo.y'"), std::string::npos);
    EXPECT_NE(message_of(with("height", 3)).find("unknown field 'geo.height'"), std::string::npos);
    EXPECT_NE(message_of({{"geo", 5}}).find("'geo' must be an object or null"), std::string::npos);
    EXPECT_NE(message_of({{"geo_lat", 5}}).find("unknown field 'geo_lat'"), std::string::npos);
    EXPECT_NE(message_of({{"elevation_m", 1e5}}).find("'elevation_m'"), std::string::npos);
    EXPECT_EQ(message_of({{"geo", kGeo}}).substr(0, 2), "ok");
}

TEST(FloorGeoFields, AnswersFoldTheColumnsBackIntoOneObjectOrNull) {
    store::Record row{7, 3, http::validated_fields(floors(), {{"name", "F"}, {"level", 0}, {"width", 1}, {"height", 1}, {"geo", kGeo}}, true)};
    row.fields.values["north_offset_deg"] = 0.0;
    row.fields.values["elevation_m"] = std::monostate{};
    const json j = http::record_json(floors(), row);
    ASSERT_TRUE(j.at("geo").is_object()) << j.dump();
    EXPECT_EQ(j.at("geo").size(), 5u);
    EXPECT_NEAR(j.at("geo").at("bearing_deg").get<double>(), 339.264, 1e-9);
    EXPECT_TRUE(j.at("elevation_m").is_null());
    EXPECT_FALSE(j.contains("geo_lat"));
    const auto g = http::georeference_of(row);
    ASSERT_TRUE(g);
    EXPECT_DOUBLE_EQ(g->at.lat, 49.46115181);
    EXPECT_DOUBLE_EQ(g->anchor.y, 25.0);
    // One member unset: no georeference, shown as null.
    row.fields.values["geo_x"] = std::monostate{};
    EXPECT_TRUE(http::record_json(floors(), row).at("geo").is_null());
    EXPECT_FALSE(http::georeference_of(row));
}

TEST(FloorGeoFields, AMapBundleFloorCarriesGeoAndElevation) {
    const json bundle = {{"map", {{"name", "Museum"}}},
                         {"buildings",
                          {{{"name", "Hall"},
                            {"floors", {{{"name", "Basement"}, {"level", -2}, {"width", 100}, {"height", 50}, {"elevation_m", -5.7}, {"geo", kGeo}}}}}}}};
    const auto b = http::parse_map_bundle(bundle);
    const auto& f = b.buildings.at(0).floors.at(0).fields;
    EXPECT_DOUBLE_EQ(f.get<double>("geo_lat"), 49.46115181);
    EXPECT_DOUBLE_EQ(f.get<double>("elevation_m"), -5.7);
    json bad = bundle;
    bad["buildings"][0]["floors"][0]["geo"]["lat"] = 100;
    try {
        http::parse_map_bundle(bad);
        ADD_FAILURE() << "accepted lat 100";
    } catch (const http::ApiError& e) {
        EXPECT_NE(std::string(e.what()).find("buildings[0].floors[0]: 'geo.lat'"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace floor_geo_fields_test
