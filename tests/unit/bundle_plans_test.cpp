// Plans inside a map bundle (http/plans/bundle_plans.hpp): the demo map's two plans land on their
// floors with links resolved from levels to floor ids, through the PUT endpoint's checks; a
// bundle plan that names a missing level, links by floor id, or fails a check is refused
// naming the floor and the feature.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "http/api_error.hpp"
#include "http/plans/bundle_plans.hpp"
#include "http/crud/store_json.hpp"
#include "store/migrations.hpp"
#include "store/sql_store.hpp"
#include "temp_dir.hpp"

namespace bundle_plans_test {
namespace {

using locus::store::kind;
using locus::store::SqlStore;
using nlohmann::json;

using locus::testing::TempDir;

json small_bundle(json ground_links, json upper_links = {{{"level", 0}, {"connector", "S"}}}, json upper_plan = nullptr) {
    auto square = [](double x0, double y0, double x1, double y1) {
        return json{{"type", "Polygon"}, {"coordinates", {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}}}};
    };
    auto plan = [&](json links) {
        return json{{"type", "FeatureCollection"},
                    {"features",
                     {{{"type", "Feature"}, {"geometry", square(0, 0, 10, 10)}, {"properties", {{"feature", "space"}, {"name", "Hall"}}}},
                      {{"type", "Feature"},
                       {"geometry", {{"type", "Point"}, {"coordinates", {5, 5}}}},
                       {"properties", {{"feature", "connector"}, {"id", "S"}, {"kind", "stairs"}, {"links", links}}}}}}};
    };
    json floors = json::array();
    floors.push_back({{"name", "Ground"}, {"level", 0}, {"width", 10.0}, {"height", 10.0}, {"plan", plan(ground_links)}});
    json upper = {{"name", "Upper"}, {"level", 1}, {"width", 10.0}, {"height", 10.0}};
    upper["plan"] = upper_plan.is_null() ? plan(upper_links) : upper_plan;
    floors.push_back(upper);
    return {{"map", {{"name", "M"}}}, {"buildings", {{{"name", "B"}, {"floors", floors}}}}};
}

// Imports the bundle and writes its plans, as locus-server --demo does.
std::int64_t import(SqlStore& store, const json& bundle) {
    const auto plans = locus::http::parse_bundle_plans(bundle);
    const auto map_id = store.import_map_bundle(locus::http::parse_map_bundle(bundle)).id;
    locus::http::put_bundle_plans(store, map_id, plans);
    return map_id;
}

std::string refusal(SqlStore& store, const json& bundle) {
    try {
        import(store, bundle);
    } catch (const locus::http::ApiError& e) {
        return std::to_string(e.status) + " " + e.code + ": " + e.what();
    }
    return "accepted";
}

TEST(BundlePlans, TheDemoMapsPlansLandOnTheirFloorsLinkedToEachOther) {
    TempDir t{"bundle"};
    SqlStore store(t.path());
    const auto map_id = import(store, json::parse(locus::server::demo_map_json()));
    const auto plans = store.plans_of_map(map_id);
    ASSERT_EQ(plans.size(), 2u);
    for (const auto& f : plans) {
        ASSERT_EQ(f.plan.connectors.size(), 2u);
        const std::int64_t other = plans[0].floor_id == f.floor_id ? plans[1].floor_id : plans[0].floor_id;
        for (const auto& c : f.plan.connectors) {
            ASSERT_EQ(c.links.size(), 1u) << c.id;
            EXPECT_EQ(c.links[0].floor_id, other) << c.id;
            EXPECT_EQ(c.links[0].connector, c.id);
        }
        EXPECT_EQ(f.plan.spaces.size(), store.rooms_of_floor(f.floor_id).size());
    }
}

TEST(BundlePlans, LinksByLevelResolveToThatBuildingsFloor) {
    TempDir t{"bundle"};
    SqlStore store(t.path());
    const auto map_id = import(store, small_bundle({{{"level", 1}, {"connector", "S"}}}));
    const auto plans = store.plans_of_map(map_id);
    ASSERT_EQ(plans.size(), 2u);
    EXPECT_EQ(plans[0].plan.connectors[0].links[0].floor_id, plans[1].floor_id);
    EXPECT_EQ(plans[1].plan.connectors[0].links[0].floor_id, plans[0].floor_id);
}

TEST(BundlePlans, ABadPlanIsRefusedNamingTheFloorAndTheFeature) {
    {
        TempDir t{"bundle"};
        SqlStore store(t.path());
        const auto r = refusal(store, small_bundle({{{"level", 7}, {"connector", "S"}}}));
        EXPECT_NE(r.find("422 invalid_field: 'buildings[0].floors[0].plan': the building has no floor at level 7"), std::string::npos) << r;
    }
    {
        TempDir t{"bundle"};
        SqlStore store(t.path());
        const auto r = refusal(store, small_bundle({{{"floor_id", 2}, {"connector", "S"}}}));
        EXPECT_NE(r.find("buildings[0].floors[0].plan.features[1]"), std::string::npos) << r;
        EXPECT_NE(r.find("{\"level\": L, \"connector\": ID}"), std::string::npos) << r;
        EXPECT_FALSE(store.has_maps());  // refused while reading, before anything was written
    }
    {
        TempDir t{"bundle"};
        SqlStore store(t.path());
        // The second plan's link must name a connector the first has (the first may name a
        // floor that has no plan yet, as with PUT).
        const auto r = refusal(store, small_bundle({{{"level", 1}, {"connector", "S"}}}, {{{"level", 0}, {"connector", "nowhere"}}}));
        EXPECT_NE(r.find("422 invalid_plan: buildings[0].floors[1].plan:"), std::string::npos) << r;
    }
    {
        TempDir t{"bundle"};
        SqlStore store(t.path());
        json bowtie = {{"type", "FeatureCollection"},
                       {"features",
                        {{{"type", "Feature"},
                          {"geometry", {{"type", "Polygon"}, {"coordinates", {{{0, 0}, {5, 0}, {5, 4}, {2, -1}, {0, 4}, {0, 0}}}}}},
                          {"properties", {{"feature", "space"}, {"name", "Twisted"}}}}}}};
        const auto r = refusal(store, small_bundle({{{"level", 1}, {"connector", "S"}}}, nullptr, bowtie));
        EXPECT_NE(r.find("422 invalid_plan: buildings[0].floors[1].plan: spaces[0] 'Twisted'"), std::string::npos) << r;
    }
}

}  // namespace
}  // namespace bundle_plans_test
