#pragma once
// Floor plans inside a map bundle (the demo map's format, schema/demo_map.json): a floor may
// carry "plan", a GeoJSON FeatureCollection as PUT /v1/floors/{id}/plan takes, except that a
// connector's links name the other floor by its level in the same building,
// {"level": 1, "connector": "S"}, since floor ids exist only once the bundle is imported.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "locus/plan/plan.hpp"
#include "store/store.hpp"

namespace locus::http {

struct BundlePlan {
    std::size_t building = 0;  // index in the bundle's buildings
    std::int64_t level = 0;    // the floor's level
    plan::Plan plan;           // links' floor_id not yet set
    std::vector<std::vector<std::int64_t>> link_levels;  // per connector, per link: the level it leads to
    std::string where;         // "buildings[0].floors[1].plan", for messages
};

// Reads every floor's "plan" (ApiError 422 naming the floor and the feature).
std::vector<BundlePlan> parse_bundle_plans(const nlohmann::json& bundle);

// After Store::import_map_bundle made map `map_id`: each plan on the floor of its level, its
// links resolved to that building's floors, written through put_checked_plan (the PUT
// endpoint's checks) in bundle order, so a link's other end may be written after it.
void put_bundle_plans(store::Store& store, std::int64_t map_id, const std::vector<BundlePlan>& plans);

}  // namespace locus::http
