// A floor's plan: GET, PUT (whole document) and DELETE /v1/floors/{id}/plan. A PUT keeps the
// floor's rooms and POIs in step with the plan (Store::put_plan), and answers every room_id
// and poi_id it kept. A GET answers the text kept until anything changes (plan_answers.hpp).
#include "http/app.hpp"
#include "http/json_text.hpp"
#include "http/plans/plan_json.hpp"
#include "http/plans/plan_put.hpp"
#include "http/validation.hpp"
#include "locus/plan/geojson.hpp"
#include "locus/plan/wgs84.hpp"

namespace locus::http {

using nlohmann::json;

namespace {
// "features[4] (space 'Lab')": where the store's refusal points, in the document as sent
// (the typed plan lists spaces and connectors apart; the client counts its features).
std::string feature_label(const json& doc, const store::PlanFeatureRefused& e) {
    const char* wanted = e.connector ? "connector" : "space";
    std::size_t seen = 0;
    const auto& features = doc.at("features");
    for (std::size_t i = 0; i < features.size(); ++i) {
        const auto& p = features[i].at("properties");
        if (p.value("feature", json()) != wanted || seen++ != e.index) continue;
        std::string label = "features[" + std::to_string(i) + "] (" + wanted;
        const auto name = p.value("name", json());
        if (name.is_string() && !name.get<std::string>().empty()) label += " '" + name.get<std::string>() + "'";
        else if (e.connector) label += " '" + p.value("id", std::string()) + "'";
        return label + ")";
    }
    return e.feature;
}

// The form a plan is asked for or sent in: ?crs=wgs84 (RFC 7946), else floor metres.
bool wants_wgs84(const httplib::Request& req) {
    if (!req.has_param("crs")) return false;
    const std::string crs = req.get_param_value("crs");
    if (crs == "wgs84") return true;
    if (crs == "floor-metres") return false;
    throw invalid_query("'crs' must be wgs84 or floor-metres");
}

const geo::FloorToEarth& georeferenced(FloorGeoCache& geo, std::int64_t floor_id, std::shared_ptr<const geo::FloorToEarth>& keep) {
    keep = geo.of_floor(floor_id);
    if (!keep)
        throw ApiError(422, "not_georeferenced",
                       "floor " + std::to_string(floor_id) + " has no georeference: PATCH /v1/floors/" + std::to_string(floor_id) +
                           " with geo {lat, lon, x, y, bearing_deg}, or POST its control points to …/georeference");
    return *keep;
}

// The stored plan as answered: in floor metres, saying so, or in WGS84.
json plan_answer(const store::StoredPlan& stored, bool wgs84, FloorGeoCache& geo, std::int64_t floor_id) {
    json out = plan_json(stored);
    if (!wgs84) {
        out["crs"] = plan::kFloorMetresCrs;
        return out;
    }
    std::shared_ptr<const geo::FloorToEarth> keep;
    return plan::plan_to_wgs84(out, georeferenced(geo, floor_id, keep));
}

}  // namespace

void App::install_plan_routes() {
    const std::string path = R"(/v1/floors/(\d+)/plan)";
    server_.Get(path, [this](const httplib::Request& req, httplib::Response& res) {
        respond_text(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const bool wgs84 = wants_wgs84(req);
            return plan_answers_.get(floor_id, wgs84, [&] {
                const auto stored = store_.plan_of_floor(floor_id);
                if (!stored) throw ApiError(404, "not_found", "floor " + std::to_string(floor_id) + " has no plan");
                return json_text(plan_answer(*stored, wgs84, geo_, floor_id));
            });
        });
    });
    server_.Put(path, [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            json doc = parse_object(req.body);
            const auto crs = plan::crs_of(doc);
            if (crs == plan::DocumentCrs::unknown)
                throw invalid_field("'crs' must be \"locus:floor-metres\", or absent (send ?crs=wgs84 for RFC 7946 positions)");
            const bool wgs84 = wants_wgs84(req) || crs == plan::DocumentCrs::wgs84;
            if (wgs84) {
                std::shared_ptr<const geo::FloorToEarth> keep;
                try {
                    doc = plan::plan_from_wgs84(doc, georeferenced(geo_, floor_id, keep));
                } catch (const plan::GeoJsonError& e) {
                    throw ApiError(422, "invalid_plan", e.what());
                }
            }
            const plan::Plan plan = parse_plan(doc);
            try {
                return std::pair{200, plan_answer(put_checked_plan(store_, floor_id, plan), wgs84, geo_, floor_id)};
            } catch (const store::PlanFeatureRefused& e) {
                throw ApiError(422, "invalid_plan", feature_label(doc, e) + ": " + e.what());
            }
        });
    });
    server_.Delete(path, [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            store_.remove_plan(parse_id(req.matches[1].str(), "floor"));
            return std::pair{204, json()};
        });
    });
}

}  // namespace locus::http
