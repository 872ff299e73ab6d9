#include "floors/floor_places_cache.hpp"

#include <string>
#include <variant>
#include <vector>

#include "store/kinds.hpp"

namespace locus::floors {

namespace {

std::vector<Poi> pois_of_floor(store::Store& store, std::int64_t floor_id) {
    std::vector<Poi> out;
    const auto page = store.list(store::kind("pois"), floor_id, 1'000'000, 0);
    for (const auto& r : page.items) {
        const auto& v = r.fields.values;
        const auto text = [&](const char* field) {
            const auto it = v.find(field);
            return it != v.end() && std::holds_alternative<std::string>(it->second) ? std::get<std::string>(it->second) : std::string();
        };
        out.push_back({r.id, text("name"), text("kind"), {r.fields.get<double>("x"), r.fields.get<double>("y")}});
    }
    return out;
}

store::FloorDrop places_drops(const store::Change& c) {
    if (!c.kind) return store::FloorDrop::none;
    const auto& name = c.kind->name;
    // A plan saved with rooms replaces them (plans keep rooms, docs/plans.md).
    if (name == "floors") return store::FloorDrop::floor;
    if (name == "rooms" || name == "pois" || ((name == "maps" || name == "buildings") && c.deleted)) return store::FloorDrop::all;
    return store::FloorDrop::none;
}

std::shared_ptr<const FloorPlaces> places_of_floor(store::Store& store, std::int64_t floor_id) {
    store.get(store::kind("floors"), floor_id);  // NotFound for a floor that is gone
    return std::make_shared<const FloorPlaces>(store.rooms_of_floor(floor_id), pois_of_floor(store, floor_id));
}

}  // namespace

FloorPlacesCache::FloorPlacesCache(store::Store& store) : cache_(store, places_of_floor, places_drops) {}

std::shared_ptr<const FloorPlaces> FloorPlacesCache::of_floor(std::int64_t floor_id) {
    try {
        return cache_.of_floor(floor_id);
    } catch (const store::NotFound&) {
        return nullptr;
    }
}

}  // namespace locus::floors
