// A floor's plan: GET, PUT (whole document) and DELETE /v1/floors/{id}/plan. A PUT keeps the
// floor's rooms and POIs in step with the plan (Store::put_plan), and answers every room_id
// and poi_id it kept.
#include "http/app.hpp"
#include "http/plan_json.hpp"
#include "http/validation.hpp"
#include "locus/plan/check.hpp"

namespace locus::http {

using nlohmann::json;

namespace {
// All of a refused plan's problems in one message, so a user fixes them in one round.
[[noreturn]] void refuse(const std::vector<std::string>& problems);

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

[[noreturn]] void refuse(const std::vector<std::string>& problems) {
    std::string message = problems.front();
    for (std::size_t i = 1; i < problems.size() && i < 20; ++i) message += "; " + problems[i];
    if (problems.size() > 20) message += "; and " + std::to_string(problems.size() - 20) + " more";
    throw ApiError(422, "invalid_plan", message);
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
            // The geometry the router relies on: simple closed rings, doors on walls, …
            if (const auto problems = plan::check_plan(plan); !problems.empty()) {
                std::vector<std::string> messages;
                for (const auto& p : problems) messages.push_back(p.feature + ": " + p.problem);
                refuse(messages);
            }
            try {
                const auto stored = store_.put_plan(floor_id, plan, [&](const std::vector<store::OtherPlan>& others) {
                    std::vector<plan::OtherFloor> floors;
                    for (const auto& o : others) floors.push_back({o.floor_id, o.plan ? &*o.plan : nullptr});
                    if (const auto problems = plan::link_problems(floor_id, plan, floors); !problems.empty()) refuse(problems);
                });
                return std::pair{200, plan_json(stored)};
            } catch (const store::PlanFeatureRefused& e) {
                refuse({feature_label(doc, e) + ": " + e.what()});
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
