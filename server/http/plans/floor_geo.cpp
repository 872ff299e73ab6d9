#include "http/plans/floor_geo.hpp"

namespace locus::http {

void add_lat_lon(nlohmann::json& j, const geo::FloorToEarth* floor, Point at) {
    if (!floor) return;
    const geo::LatLon p = floor->to_geodetic(at);
    j["lat"] = p.lat;
    j["lon"] = p.lon;
}

}  // namespace locus::http
