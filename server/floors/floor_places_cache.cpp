#include "floors/floor_places_cache.hpp"

#include <string>
#include <variant>
#include <vector>

#include "store/kinds.hpp"

namespace locus::floors {

FloorPlacesCache::FloorPlacesCache(store::Store& store) : store_(store) {
    token_ = store_.subscribe([this](const store::Change& c) { on_change(c); });
}

FloorPlacesCache::~FloorPlacesCache() { store_.unsubscribe(token_); }

void FloorPlacesCache::on_change(const store::Change& c) {
    if (!c.kind) return;
    const auto& name = c.kind->name;
    std::lock_guard lock(mu_);
    if (name == "floors") {
        // A plan saved with rooms replaces them (plans keep rooms, docs/plans.md).
        floors_.erase(c.id);
        ++generation_;
    } else if (name == "rooms" || name == "pois" || ((name == "maps" || name == "buildings") && c.deleted)) {
        floors_.clear();
        ++generation_;
    }
}

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

}  // namespace

std::shared_ptr<const FloorPlaces> FloorPlacesCache::of_floor(std::int64_t floor_id) {
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mu_);
        if (const auto it = floors_.find(floor_id); it != floors_.end()) return it->second;
        generation = generation_;
    }
    std::shared_ptr<const FloorPlaces> read;
    try {
        store_.get(store::kind("floors"), floor_id);  // NotFound for a floor that is gone
        read = std::make_shared<const FloorPlaces>(store_.rooms_of_floor(floor_id), pois_of_floor(store_, floor_id));
    } catch (const store::NotFound&) {
        return nullptr;
    }
    std::lock_guard lock(mu_);
    if (generation == generation_) floors_[floor_id] = read;
    return read;
}

}  // namespace locus::floors
