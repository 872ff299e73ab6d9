#include "http/plans/georeference_request.hpp"

#include "http/api_error.hpp"
#include "http/validation.hpp"
#include "store/kinds.hpp"

namespace locus::http {

std::vector<geo::ControlPoint> parse_control_points(const std::string& body) {
    const auto j = parse_object(body);
    only_fields(j, {"points"}, "");
    const auto it = j.find("points");
    if (it == j.end()) throw invalid_field("missing field 'points'");
    if (!it->is_array()) throw invalid_field("'points' must be an array of {x, y, lat, lon}");
    if (it->size() < 3) throw invalid_field("'points' needs at least 3 control points, not " + std::to_string(it->size()));
    if (it->size() > kMaxControlPoints)
        throw invalid_field("'points' holds more than " + std::to_string(kMaxControlPoints) + " control points");
    std::vector<geo::ControlPoint> out;
    out.reserve(it->size());
    for (std::size_t i = 0; i < it->size(); ++i) {
        const std::string where = "points[" + std::to_string(i) + "]";
        const auto& p = (*it)[i];
        if (!p.is_object()) throw invalid_field("'" + where + "' must be an object {x, y, lat, lon}");
        only_fields(p, {"x", "y", "lat", "lon"}, where);
        geo::ControlPoint c;
        c.floor.x = finite_number(p, "x", where, -store::kMaxCoordinate, store::kMaxCoordinate);
        c.floor.y = finite_number(p, "y", where, -store::kMaxCoordinate, store::kMaxCoordinate);
        c.earth.lat = finite_number(p, "lat", where, -90.0, 90.0);
        c.earth.lon = finite_number(p, "lon", where, -180.0, 180.0);
        out.push_back(c);
    }
    return out;
}

ApiError fit_problem_error(geo::FitProblem problem) {
    switch (problem) {
        case geo::FitProblem::too_few: return invalid_field("'points' needs at least 3 control points");
        case geo::FitProblem::collinear:
            return invalid_field("'points' are collinear (or coincide) on the floor: they fix no rotation");
        case geo::FitProblem::too_spread:
            return invalid_field("'points' spread more than " + std::to_string(static_cast<int>(geo::kMaxFitSpreadM / 1000)) +
                                 " km from their centre: a floor's tangent plane covers a campus");
    }
    return invalid_field("'points' cannot be fitted");
}

nlohmann::json georeference_json(const geo::Georeference& g) {
    return {{"lat", g.at.lat}, {"lon", g.at.lon}, {"x", g.anchor.x}, {"y", g.anchor.y}, {"bearing_deg", g.bearing_deg}};
}

nlohmann::json fit_json(const geo::GeoreferenceFit& fit) {
    return {{"geo", georeference_json(fit.georeference)},
            {"residuals_m", fit.residuals_m},
            {"rms_m", fit.rms_m},
            {"scale", fit.scale}};
}

}  // namespace locus::http
