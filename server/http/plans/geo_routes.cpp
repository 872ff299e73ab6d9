// POST /v1/floors/{id}/georeference[?dry_run=true]: fits a floor's georeference to surveyed
// control points {x, y, lat, lon} and stores it (docs/geo.md). The answer is the stored
// georeference with the fit's residuals, RMS and similarity scale; with dry_run nothing is
// stored. (PATCH /v1/floors/{id} with "geo" sets one directly: crud_routes.cpp.)
#include "http/app.hpp"
#include "http/plans/georeference_request.hpp"
#include "http/crud/store_json.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

void App::install_geo_routes() {
    server_.Post(R"(/v1/floors/(\d+)/georeference)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "floor");
            bool dry_run = false;
            if (req.has_param("dry_run")) {
                const auto v = req.get_param_value("dry_run");
                if (v != "true" && v != "false") throw invalid_query("'dry_run' must be true or false");
                dry_run = v == "true";
            }
            const auto& floors = store::kind("floors");
            store_.get(floors, id);  // 404 for an unknown floor, before the body is judged
            const auto r = geo::fit_georeference(parse_control_points(req.body));
            if (!r.fit) throw fit_problem_error(r.problem.value_or(geo::FitProblem::too_few));
            json out = fit_json(*r.fit);
            if (!dry_run) {
                const auto& g = r.fit->georeference;
                const store::Fields geo{{"geo_lat", g.at.lat}, {"geo_lon", g.at.lon}, {"geo_x", g.anchor.x},
                                        {"geo_y", g.anchor.y}, {"geo_bearing_deg", g.bearing_deg}};
                out["floor"] = record_json(floors, store_.update(floors, id, geo));
            }
            out["stored"] = !dry_run;
            return std::pair{200, std::move(out)};
        });
    });
}

}  // namespace locus::http
