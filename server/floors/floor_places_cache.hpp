#pragma once
// Each floor's rooms and POIs (locus/floor_places.hpp), for the `room` and `nearby` of every
// position the server answers (docs/api.md, "Where am I, in words"). FloorPlacesCache reads a
// floor's rooms and POIs once and keeps them indexed until the change feed says a room, a POI
// or the floor may have changed (a room's or POI's change names no floor, so it drops every
// floor: writes of either are rare beside the answers that read them), so an answer costs one
// hash lookup under a mutex per floor, no query.
#include <cstdint>
#include <memory>

#include "locus/floor_places.hpp"
#include "store/floor_cache.hpp"
#include "store/store.hpp"

namespace locus::floors {

class FloorPlacesCache {
public:
    explicit FloorPlacesCache(store::Store& store);

    // Null when the floor no longer exists.
    std::shared_ptr<const FloorPlaces> of_floor(std::int64_t floor_id);

private:
    store::FloorCache<FloorPlaces> cache_;
};

}  // namespace locus::floors
