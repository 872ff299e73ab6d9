#pragma once
// "room" and "nearby" in every JSON answer that places a position on a floor (docs/api.md,
// "Where am I, in words"): the room that holds it ({id, name}, or null) and the POIs within the
// checkpoint radius (locus::kDefaultCheckpointRadius, 1.5 m), nearest first, each {poi_id,
// name, kind, distance_m}; [] when none. The rooms and POIs themselves:
// floors/floor_places_cache.hpp.
#include <nlohmann/json.hpp>

#include "floors/floor_places_cache.hpp"
#include "http/plans/floor_geo.hpp"
#include "locus/floor_places.hpp"

namespace locus::http {

// What an answer places a position with: the floors' georeferences, rooms and POIs.
struct PositionViews {
    FloorGeoCache& geo;
    floors::FloorPlacesCache& places;
};

// Adds "room" and "nearby" of floor point `at` to `j` (null and [] for a floor that is gone).
void add_places(nlohmann::json& j, const FloorPlaces* places, Point at);

// "nearby"'s array alone.
nlohmann::json nearby_json(const FloorPlaces* places, Point at);

}  // namespace locus::http
