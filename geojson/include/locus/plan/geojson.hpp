#pragma once
// A floor plan's exchange form: a GeoJSON FeatureCollection in floor metres (x right, y up),
// each feature saying what it is in properties.feature:
//   space      Polygon            name, kind ("room", "corridor", …), tags [..], room_id
//   wall       LineString
//   door       Point | LineString name; a Point opens a standard-width gap in the wall under it
//   connector  Point              id, kind (stairs|elevator|escalator|ramp), name, step_free,
//                                 seconds_per_level, links [{floor_id, connector}], poi_id
// The server stores it, the REST client reads it for map matching, and the CLI imports,
// exports and writes it (plan from-image), all through these two functions.
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "locus/plan/plan.hpp"

namespace locus::plan {

// What is wrong with a document, starting with where: "features[3] (space 'Lab'): …".
struct GeoJsonError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// Members a stored plan carries beside "features" (the server writes them on GET), accepted
// and ignored on reading so that what was read can be written back.
// `crs`, when present, must name floor metres (wgs84.hpp converts the other form first).
inline constexpr const char* kPlanMetaMembers[] = {"floor_id", "version", "updated_at", "bbox", "crs"};

// Reads and checks the document's form (types, finite coordinates within ±1e5 m, closed
// rings, sizes, unique connector ids); throws GeoJsonError naming the offending feature. The
// geometry itself (self-intersections, doors on walls, links) is check_plan's (check.hpp).
Plan from_geojson(const nlohmann::json& doc);

// The plan as a FeatureCollection, in the order from_geojson reads (spaces, walls, doors,
// connectors): from_geojson(to_geojson(p)) == p.
nlohmann::json to_geojson(const Plan& plan);

// [[x, y], …]: a GeoJSON LineString's or ring's coordinates (also a route's legs).
nlohmann::json geojson_positions(const std::vector<Point>& pts);

}  // namespace locus::plan
