#include "locus/plan/wgs84.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "locus/plan/geojson.hpp"

namespace locus::plan {

using nlohmann::json;

namespace {

double seven_decimals(double v) { return std::round(v * 1e7) / 1e7; }

struct Box {
    double west = std::numeric_limits<double>::infinity(), south = west;
    double east = -west, north = -west;
    void add(double lon, double lat) {
        west = std::min(west, lon);
        east = std::max(east, lon);
        south = std::min(south, lat);
        north = std::max(north, lat);
    }
};

// Twice the signed area of a ring (positive: counter-clockwise), in the ring's own units.
double signed_area(const json& ring) {
    double a = 0;
    for (std::size_t i = 0; i + 1 < ring.size(); ++i)
        a += ring[i][0].get<double>() * ring[i + 1][1].get<double>() - ring[i + 1][0].get<double>() * ring[i][1].get<double>();
    return a;
}

// Every position of a geometry's coordinates, mapped by `f`; `depth` is how deep the
// positions lie (Point 0, LineString 1, Polygon 2).
template <typename F>
json map_positions(const json& coords, int depth, const F& f) {
    if (depth == 0) return f(coords);
    json out = json::array();
    for (const auto& c : coords) out.push_back(map_positions(c, depth - 1, f));
    return out;
}

int depth_of(const json& geometry, const std::string& where) {
    const std::string type = geometry.value("type", std::string());
    if (type == "Point") return 0;
    if (type == "LineString") return 1;
    if (type == "Polygon") return 2;
    throw GeoJsonError(where + ": a plan has Point, LineString and Polygon geometries, not '" + type + "'");
}

// Applies `f` to every position of every feature, giving each position its feature's name
// for errors.
template <typename F>
json map_features(const json& doc, const F& f) {
    json out = doc;
    if (!out.contains("features") || !out["features"].is_array()) throw GeoJsonError("'features' must be an array");
    for (std::size_t i = 0; i < out["features"].size(); ++i) {
        auto& feature = out["features"][i];
        const std::string where = "features[" + std::to_string(i) + "]";
        if (!feature.is_object() || !feature.contains("geometry") || !feature["geometry"].is_object())
            throw GeoJsonError(where + ": must be a GeoJSON Feature with a geometry");
        auto& g = feature["geometry"];
        const int depth = depth_of(g, where);
        if (!g.contains("coordinates")) throw GeoJsonError(where + ": the geometry has no coordinates");
        g["coordinates"] = map_positions(g["coordinates"], depth, [&](const json& p) { return f(p, where); });
        if (depth == 2) {
            // RFC 7946 §3.1.6: exterior counter-clockwise, holes clockwise.
            auto& rings = g["coordinates"];
            for (std::size_t r = 0; r < rings.size(); ++r) {
                const bool ccw = signed_area(rings[r]) > 0;
                if ((r == 0) != ccw) std::reverse(rings[r].begin(), rings[r].end());
            }
        }
    }
    return out;
}

bool is_number_pair(const json& p) { return p.is_array() && p.size() >= 2 && p[0].is_number() && p[1].is_number(); }

}  // namespace

DocumentCrs crs_of(const json& doc) {
    const auto it = doc.find("crs");
    if (it == doc.end()) return DocumentCrs::floor_metres;
    std::string name;
    if (it->is_string()) name = it->get<std::string>();
    else if (it->is_object() && it->contains("properties") && (*it)["properties"].is_object())
        name = (*it)["properties"].value("name", std::string());
    if (name == kFloorMetresCrs) return DocumentCrs::floor_metres;
    if (name == "urn:ogc:def:crs:OGC:1.3:CRS84" || name == "urn:ogc:def:crs:OGC::CRS84" || name == "EPSG:4326" ||
        name == "wgs84")
        return DocumentCrs::wgs84;
    return DocumentCrs::unknown;
}

json plan_to_wgs84(const json& doc, const geo::FloorToEarth& earth) {
    Box box;
    json out = map_features(doc, [&](const json& p, const std::string&) {
        const auto ll = earth.to_geodetic({p[0].get<double>(), p[1].get<double>()});
        const double lon = seven_decimals(ll.lon), lat = seven_decimals(ll.lat);
        box.add(lon, lat);
        return json::array({lon, lat});
    });
    out.erase("crs");
    if (box.west <= box.east) out["bbox"] = json::array({box.west, box.south, box.east, box.north});
    else out.erase("bbox");
    return out;
}

json plan_from_wgs84(const json& doc, const geo::FloorToEarth& earth) {
    json out = map_features(doc, [&](const json& p, const std::string& where) {
        if (!is_number_pair(p)) throw GeoJsonError(where + ": a position must be [longitude, latitude]");
        const double lon = p[0].get<double>(), lat = p[1].get<double>();
        if (!std::isfinite(lon) || !std::isfinite(lat) || lon < -180 || lon > 180 || lat < -90 || lat > 90)
            throw GeoJsonError(where + ": [" + std::to_string(lon) + ", " + std::to_string(lat) +
                               "] is not a longitude in [-180, 180] and a latitude in [-90, 90]");
        const Point at = earth.to_floor({lat, lon});
        return json::array({at.x, at.y});
    });
    out.erase("bbox");  // in degrees: not the floor's
    out["crs"] = kFloorMetresCrs;
    return out;
}

}  // namespace locus::plan
