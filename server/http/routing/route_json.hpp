#pragma once
// A route as POST /v1/maps/{id}/route answers it; the relative position of two tracks
// (track_routes.cpp) answers the walk between them in the same form.
#include <nlohmann/json.hpp>

#include "http/plans/floor_geo.hpp"
#include "locus/plan/route.hpp"

namespace locus::http {

// On a georeferenced floor "from" and "to" carry "lat"/"lon", and a leg "path_lat_lon", its
// path's points as [lat, lon] (docs/geo.md).
nlohmann::json route_json(const plan::Route& r, FloorGeoCache& geo);

}  // namespace locus::http
