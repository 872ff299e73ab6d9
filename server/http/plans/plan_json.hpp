#pragma once
// A floor plan on the wire: the GeoJSON codec (locus/plan/geojson.hpp) with the API's errors
// and the stored plan's floor_id, version and updated_at beside "features".
#include <nlohmann/json.hpp>

#include "locus/plan/plan.hpp"
#include "store/documents.hpp"

namespace locus::http {

// plan::from_geojson, its errors as ApiError 422 invalid_plan naming the offending feature.
plan::Plan parse_plan(const nlohmann::json& doc);

// [[x, y], …]: a GeoJSON LineString's or ring's coordinates (also a route's legs).
nlohmann::json positions_json(const std::vector<Point>& pts);

// The stored plan as GeoJSON, with "floor_id", "version" and "updated_at" beside "features".
nlohmann::json plan_json(const store::StoredPlan& stored);

}  // namespace locus::http
