// A floor's plan: GET, PUT (whole document) and DELETE /v1/floors/{id}/plan. A PUT keeps the
// floor's rooms and POIs in step with the plan (Store::put_plan), and answers every room_id
// and poi_id it kept.
#include "http/app.hpp"
#include "http/plan_json.hpp"
#include "http/plan_put.hpp"
#include "http/validation.hpp"

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

}  // namespace

void App::install_plan_routes() {
    const std::string path = R"(/v1/floors/(\d+)/plan)";
    server_.Get(path, [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const auto stored = store_.plan_of_floor(floor_id);
            if (!stored) throw ApiError(404, "not_found", "floor " + std::to_string(floor_id) + " has no plan");
            return std::pair{200, plan_json(*stored)};
        });
    });
    server_.Put(path, [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const json doc = parse_object(req.body);
            const plan::Plan plan = parse_plan(doc);
            try {
                return std::pair{200, plan_json(put_checked_plan(store_, floor_id, plan))};
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
