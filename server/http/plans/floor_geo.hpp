#pragma once
// "lat" and "lon" in the JSON answers that place a position on a georeferenced floor (the
// georeferences themselves: floors/floor_geo.hpp).
#include <nlohmann/json.hpp>

#include "floors/floor_geo.hpp"
#include "locus/geometry.hpp"

namespace locus::http {

using floors::FloorGeoCache;
using floors::georeference_of;

// Adds "lat" and "lon" of floor point `at` to `j` when the floor is georeferenced; leaves `j`
// as it was otherwise.
void add_lat_lon(nlohmann::json& j, const geo::FloorToEarth* floor, Point at);

}  // namespace locus::http
