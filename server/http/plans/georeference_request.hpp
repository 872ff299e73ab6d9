#pragma once
// POST /v1/floors/{id}/georeference (geo_routes.cpp): the control points of the body, and the
// answer's JSON. Pure: no store.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "http/api_error.hpp"
#include "locus/geo/georeference.hpp"

namespace locus::http {

inline constexpr std::size_t kMaxControlPoints = 1000;

// {"points": [{x, y, lat, lon}, ...]}: 3 to kMaxControlPoints points, finite numbers, lat in
// [-90, 90], lon in [-180, 180], x and y within the floors' coordinate bound. Throws ApiError
// (400 invalid_json, 422 naming the field) for anything else; collinear points are the fit's
// to find (fit_problem_error).
std::vector<geo::ControlPoint> parse_control_points(const std::string& body);
// 422 naming 'points' for a set of control points the fit refused.
ApiError fit_problem_error(geo::FitProblem problem);

// A georeference as a floor shows it: {lat, lon, x, y, bearing_deg}.
nlohmann::json georeference_json(const geo::Georeference& g);
// {"geo", "residuals_m", "rms_m", "scale"}.
nlohmann::json fit_json(const geo::GeoreferenceFit& fit);

}  // namespace locus::http
