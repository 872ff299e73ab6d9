// A floor's plan: GET, PUT (whole document) and DELETE /v1/floors/{id}/plan.
#include "http/app.hpp"
#include "http/plan_json.hpp"
#include "http/validation.hpp"
#include "locus/plan/check.hpp"

namespace locus::http {

using nlohmann::json;

namespace {
// All of a refused plan's problems in one message, so a user fixes them in one round.
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
            const plan::Plan plan = parse_plan(parse_object(req.body));
            // The geometry the router relies on: simple closed rings, doors on walls, …
            if (const auto problems = plan::check_plan(plan); !problems.empty()) {
                std::vector<std::string> messages;
                for (const auto& p : problems) messages.push_back(p.feature + ": " + p.problem);
                refuse(messages);
            }
            const auto stored = store_.put_plan(floor_id, plan, [&](const std::vector<store::OtherPlan>& others) {
                std::vector<plan::OtherFloor> floors;
                for (const auto& o : others) floors.push_back({o.floor_id, o.plan ? &*o.plan : nullptr});
                if (const auto problems = plan::link_problems(floor_id, plan, floors); !problems.empty()) refuse(problems);
            });
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
