// A floor's plan: GET, PUT (whole document) and DELETE /v1/floors/{id}/plan.
#include "http/app.hpp"
#include "http/plan_json.hpp"
#include "http/plan_put.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

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
            const plan::Plan plan = parse_plan(parse_object(req.body));
            const auto stored = put_checked_plan(store_, floor_id, plan);
            return std::pair{200, plan_json(stored)};
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
