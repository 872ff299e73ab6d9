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

FloorGeoCache::FloorGeoCache(store::Store& store) : store_(store) {
    token_ = store_.subscribe([this](const store::Change& c) { on_change(c); });
}

FloorGeoCache::~FloorGeoCache() { store_.unsubscribe(token_); }

void FloorGeoCache::on_change(const store::Change& c) {
    if (!c.kind) return;
    const auto name = c.kind->name;
    if (name == "floors" && c.plan) return;  // the plan, not the row
    std::lock_guard lock(mu_);
    if (name == "floors") {
        floors_.erase(c.id);
        ++generation_;
    } else if ((name == "maps" || name == "buildings") && c.deleted) {
        // Their floors go by cascade without a change each (and "everything changed" from
        // another server sharing PostgreSQL comes as a deleted map).
        floors_.clear();
        ++generation_;
    }
}

std::shared_ptr<const geo::FloorToEarth> FloorGeoCache::of_floor(std::int64_t floor_id) {
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mu_);
        if (const auto it = floors_.find(floor_id); it != floors_.end()) return it->second;
        generation = generation_;
    }
    std::shared_ptr<const geo::FloorToEarth> read;
    try {
        if (const auto g = georeference_of(store_.get(store::kind("floors"), floor_id)))
            read = std::make_shared<const geo::FloorToEarth>(*g);
    } catch (const store::NotFound&) {
        return nullptr;  // not kept: ids are never reused, but nothing asks twice for a gone floor
    }
    std::lock_guard lock(mu_);
    if (generation == generation_) floors_[floor_id] = read;
    return read;
}

}  // namespace locus::floors
