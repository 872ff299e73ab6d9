#pragma once
// A floor plan's exchange form: a GeoJSON FeatureCollection in floor metres (x right, y up),
// each feature saying what it is in properties.feature:
//   space      Polygon            name, kind ("room", "corridor", …), tags [..], room_id
//   wall       LineString
//   door       Point | LineString name; a Point opens a standard-width gap in the wall under it
//   connector  Point              id, kind (stairs|elevator|escalator|ramp), name, step_free,
//                                 seconds_per_level, links [{floor_id, connector}]
#include <nlohmann/json.hpp>

#include "locus/plan/plan.hpp"
#include "store/documents.hpp"

namespace locus::http {

// Reads and checks the document's form (types, finite coordinates within ±1e5 m, closed
// rings, sizes); throws ApiError 422 invalid_plan naming the offending feature. The geometry
// itself (self-intersections, doors on walls, links) is checked by the plan's own checks.
plan::Plan parse_plan(const nlohmann::json& doc);

// [[x, y], …]: a GeoJSON LineString's or ring's coordinates (also a route's legs).
nlohmann::json positions_json(const std::vector<Point>& pts);

// The stored plan as GeoJSON, with "floor_id", "version" and "updated_at" beside "features".
nlohmann::json plan_json(const store::StoredPlan& stored);

}  // namespace locus::http
