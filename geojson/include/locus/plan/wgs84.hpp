#pragma once
// A plan document in RFC 7946 form: longitude and latitude (WGS84) instead of floor metres,
// for floors with a georeference (locus/geo/georeference.hpp), so any GeoJSON tool shows it
// where the building stands. Floor metres stay the API's default form; a document in them
// says so with `"crs": "locus:floor-metres"` (kFloorMetresCrs), one in WGS84 has no `crs`
// member (RFC 7946 §4 dropped it), or the old-style CRS84 name when a client sends one.
//
// Positions are written with 7 decimals (about 1 cm), polygons wound by the right-hand rule
// (RFC 7946 §3.1.6: exterior rings counter-clockwise, holes clockwise) and the collection
// gets a `bbox` [west, south, east, north]. Cost: one pass over the coordinates, a tangent-
// plane conversion each (a few dozen floating-point operations).
#include <nlohmann/json.hpp>
#include <string_view>

#include "locus/geo/georeference.hpp"

namespace locus::plan {

inline constexpr const char* kFloorMetresCrs = "locus:floor-metres";

// Which form a document says it is in: its `crs` member, when it has one.
enum class DocumentCrs { floor_metres, wgs84, unknown };
DocumentCrs crs_of(const nlohmann::json& doc);

// `doc` (a plan FeatureCollection in floor metres, as to_geojson writes it) in WGS84.
nlohmann::json plan_to_wgs84(const nlohmann::json& doc, const geo::FloorToEarth& earth);

// `doc` in WGS84 back in floor metres, ready for from_geojson; GeoJsonError (geojson.hpp)
// names the feature of a position that is not [longitude, latitude] within range.
nlohmann::json plan_from_wgs84(const nlohmann::json& doc, const geo::FloorToEarth& earth);

}  // namespace locus::plan
