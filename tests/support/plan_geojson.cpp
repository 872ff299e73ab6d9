#include "plan_geojson.hpp"

namespace locus::testing {

using nlohmann::json;

json feature(const char* kind, json geometry, json properties) {
    properties["feature"] = kind;
    return {{"type", "Feature"}, {"geometry", std::move(geometry)}, {"properties", std::move(properties)}};
}

json polygon(const std::vector<std::pair<double, double>>& ring) {
    json r = json::array();
    for (auto [x, y] : ring) r.push_back({x, y});
    return {{"type", "Polygon"}, {"coordinates", json::array({r})}};
}

json rect_polygon(double x0, double y0, double x1, double y1) { return polygon({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}); }

json line(const std::vector<std::pair<double, double>>& pts) {
    json c = json::array();
    for (auto [x, y] : pts) c.push_back({x, y});
    return {{"type", "LineString"}, {"coordinates", c}};
}

json point(double x, double y) { return {{"type", "Point"}, {"coordinates", {x, y}}}; }

}  // namespace locus::testing
