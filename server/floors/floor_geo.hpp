#pragma once
// Floors' georeferences (docs/geo.md) for everything that places a position on a floor: a
// localize answer, a track's fix, a route's points carry "lat"/"lon" when their floor has one,
// and a thin client's GNSS fixes are turned into floor coordinates with it. FloorGeoCache
// reads a floor's row once and keeps its georeference (or that it has none) until the change
// feed says the floor may have changed, so an answer does one hash lookup under a mutex per
// floor, no query.
#include <cstdint>
#include <memory>
#include <optional>

#include "locus/geo/georeference.hpp"
#include "store/floor_cache.hpp"
#include "store/store.hpp"

namespace locus::floors {

// The floor row's georeference; nullopt unless all of its geo_* columns are set.
std::optional<geo::Georeference> georeference_of(const store::Record& floor);

class FloorGeoCache {
public:
    explicit FloorGeoCache(store::Store& store);

    // Null when the floor has no georeference or no longer exists.
    std::shared_ptr<const geo::FloorToEarth> of_floor(std::int64_t floor_id);

private:
    store::FloorCache<geo::FloorToEarth> cache_;  // null kept: no georeference
};

}  // namespace locus::floors
