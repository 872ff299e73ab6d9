#pragma once
// Each floor's rooms and POIs (locus/floor_places.hpp), for the `room` and `nearby` of every
// position the server answers (docs/api.md, "Where am I, in words"). FloorPlacesCache reads a
// floor's rooms and POIs once and keeps them indexed until the change feed says a room, a POI
// or the floor may have changed (a room's or POI's change names no floor, so it drops every
// floor: writes of either are rare beside the answers that read them), so an answer costs one
// hash lookup under a mutex per floor, no query.
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "locus/floor_places.hpp"
#include "store/store.hpp"

namespace locus::floors {

class FloorPlacesCache {
public:
    explicit FloorPlacesCache(store::Store& store);
    ~FloorPlacesCache();
    FloorPlacesCache(const FloorPlacesCache&) = delete;
    FloorPlacesCache& operator=(const FloorPlacesCache&) = delete;

    // Null when the floor no longer exists.
    std::shared_ptr<const FloorPlaces> of_floor(std::int64_t floor_id);

private:
    void on_change(const store::Change& change);

    store::Store& store_;
    std::mutex mu_;
    std::unordered_map<std::int64_t, std::shared_ptr<const FloorPlaces>> floors_;
    std::uint64_t generation_ = 0;  // bumped by every invalidation: a read that raced a write is not kept
    std::size_t token_ = 0;
};

}  // namespace locus::floors
