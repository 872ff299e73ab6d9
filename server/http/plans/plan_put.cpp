#include "http/plans/plan_put.hpp"

#include <string>
#include <vector>

#include "http/api_error.hpp"
#include "locus/plan/check.hpp"

namespace locus::http {

namespace {
// All of a refused plan's problems in one message, so a user fixes them in one round.
[[noreturn]] void refuse(const std::vector<std::string>& problems) {
    std::string message = problems.front();
    for (std::size_t i = 1; i < problems.size() && i < 20; ++i) message += "; " + problems[i];
    if (problems.size() > 20) message += "; and " + std::to_string(problems.size() - 20) + " more";
    throw ApiError(422, "invalid_plan", message);
}
}  // namespace

store::StoredPlan put_checked_plan(store::Store& store, std::int64_t floor_id, const plan::Plan& plan) {
    // The geometry the router relies on: simple closed rings, doors on walls, …
    if (const auto problems = plan::check_plan(plan); !problems.empty()) {
        std::vector<std::string> messages;
        for (const auto& p : problems) messages.push_back(p.feature + ": " + p.problem);
        refuse(messages);
    }
    return store.put_plan(floor_id, plan, [&](const std::vector<store::OtherPlan>& others) {
        std::vector<plan::OtherFloor> floors;
        for (const auto& o : others) floors.push_back({o.floor_id, o.plan ? &*o.plan : nullptr});
        if (const auto problems = plan::link_problems(floor_id, plan, floors); !problems.empty()) refuse(problems);
    });
}

}  // namespace locus::http
