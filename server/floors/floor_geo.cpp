#include "floors/floor_geo.hpp"

#include <variant>

#include "store/kinds.hpp"

namespace locus::floors {

std::optional<geo::Georeference> georeference_of(const store::Record& floor) {
    const auto& v = floor.fields.values;
    double got[5];
    int i = 0;
    for (const char* column : {"geo_lat", "geo_lon", "geo_x", "geo_y", "geo_bearing_deg"}) {
        const auto it = v.find(column);
        if (it == v.end() || !std::holds_alternative<double>(it->second)) return std::nullopt;
        got[i++] = std::get<double>(it->second);
    }
    return geo::Georeference{{got[0], got[1]}, {got[2], got[3]}, got[4]};
}

namespace {

store::FloorDrop geo_drops(const store::Change& c) {
    if (!c.kind) return store::FloorDrop::none;
    const auto& name = c.kind->name;
    if (name == "floors") return c.plan ? store::FloorDrop::none : store::FloorDrop::floor;  // the plan is not the row
    // Their floors go by cascade without a change each (and "everything changed" from another
    // server sharing PostgreSQL comes as a deleted map).
    if ((name == "maps" || name == "buildings") && c.deleted) return store::FloorDrop::all;
    return store::FloorDrop::none;
}

std::shared_ptr<const geo::FloorToEarth> geo_of_floor(store::Store& store, std::int64_t floor_id) {
    if (const auto g = georeference_of(store.get(store::kind("floors"), floor_id))) return std::make_shared<const geo::FloorToEarth>(*g);
    return nullptr;
}

}  // namespace

FloorGeoCache::FloorGeoCache(store::Store& store) : cache_(store, geo_of_floor, geo_drops) {}

std::shared_ptr<const geo::FloorToEarth> FloorGeoCache::of_floor(std::int64_t floor_id) {
    try {
        return cache_.of_floor(floor_id);
    } catch (const store::NotFound&) {
        return nullptr;  // not kept: ids are never reused, but nothing asks twice for a gone floor
    }
}

}  // namespace locus::floors
