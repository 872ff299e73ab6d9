#pragma once
// Floor-plan GeoJSON for the plan and route tests: a feature and its geometries.
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

namespace locus::testing {

// {"type":"Feature", geometry, properties + {"feature": kind}}.
nlohmann::json feature(const char* kind, nlohmann::json geometry, nlohmann::json properties = nlohmann::json::object());
nlohmann::json polygon(const std::vector<std::pair<double, double>>& ring);
nlohmann::json rect_polygon(double x0, double y0, double x1, double y1);
nlohmann::json line(const std::vector<std::pair<double, double>>& pts);
nlohmann::json point(double x, double y);

}  // namespace locus::testing
