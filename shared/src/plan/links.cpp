#include <map>
#include <string>

#include "locus/plan/check.hpp"
#include "locus/plan/plan.hpp"

namespace locus::plan {

namespace {
const Connector* find(const Plan& p, std::string_view id) {
    for (const auto& c : p.connectors)
        if (c.id == id) return &c;
    return nullptr;
}
bool links_to(const Connector& c, std::int64_t floor_id, std::string_view connector) {
    for (const auto& l : c.links)
        if (l.floor_id == floor_id && l.connector == connector) return true;
    return false;
}
std::string named(const Connector& c) { return "connector '" + c.id + "'"; }

// What is wrong with one link of a connector on floor `floor_id`, given the map's floors
// (null plan: that floor has none yet, so the link is not checked further); "" when nothing.
// `require_back`: the connector there must link back (a whole building's final state);
// without it a link may wait for its partner floor's next plan.
std::string link_problem(std::int64_t floor_id, const Connector& c, const ConnectorLink& l,
                         const std::map<std::int64_t, const Plan*>& floors, bool require_back) {
    const std::string to = "floor " + std::to_string(l.floor_id) + " connector '" + l.connector + "'";
    if (l.floor_id == floor_id) return "links to its own floor";
    const auto it = floors.find(l.floor_id);
    if (it == floors.end()) return "links to floor " + std::to_string(l.floor_id) + ", which is not a floor of this map";
    if (!it->second) return "";
    const Connector* other = find(*it->second, l.connector);
    if (!other) return "links to " + to + ", which that floor's plan does not have";
    if (require_back && !links_to(*other, floor_id, c.id)) return "links to " + to + ", which does not link back";
    return "";
}
}  // namespace

std::vector<std::string> link_problems(std::int64_t floor_id, const Plan& plan, const std::vector<OtherFloor>& others) {
    std::map<std::int64_t, const Plan*> floors;  // the map's other floors; null: no plan yet
    for (const auto& o : others) floors[o.floor_id] = o.plan;
    std::vector<std::string> problems;
    for (const auto& c : plan.connectors) {
        for (const auto& l : c.links)
            if (const std::string p = link_problem(floor_id, c, l, floors, false); !p.empty())
                problems.push_back(named(c) + " " + p);
    }
    return problems;
}

std::vector<PlanProblem> check_links(const std::vector<std::pair<std::int64_t, const Plan*>>& floors) {
    std::vector<PlanProblem> out;
    std::map<std::int64_t, const Plan*> by_id;
    for (const auto& [id, plan] : floors)
        if (!by_id.emplace(id, plan).second) out.push_back({"floor " + std::to_string(id), "floor id given twice"});
    // Every link is checked from its own end, so an unreturned link is reported once.
    for (const auto& [floor_id, plan] : floors)
        for (std::size_t i = 0; i < plan->connectors.size(); ++i) {
            const Connector& c = plan->connectors[i];
            const std::string feature = "floor " + std::to_string(floor_id) + " connectors[" + std::to_string(i) + "] '" + c.id + "'";
            for (const ConnectorLink& l : c.links)
                if (std::string p = link_problem(floor_id, c, l, by_id, true); !p.empty()) out.push_back({feature, std::move(p)});
        }
    return out;
}

}  // namespace locus::plan
