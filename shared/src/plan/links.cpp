#include <map>
#include <string>

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
}  // namespace

std::vector<std::string> link_problems(std::int64_t floor_id, const Plan& plan, const std::vector<OtherFloor>& others) {
    std::map<std::int64_t, const Plan*> floors;  // the map's other floors; null: no plan yet
    for (const auto& o : others) floors[o.floor_id] = o.plan;
    std::vector<std::string> problems;
    for (const auto& c : plan.connectors) {
        for (const auto& l : c.links) {
            const std::string to = "floor " + std::to_string(l.floor_id) + " connector '" + l.connector + "'";
            if (l.floor_id == floor_id) {
                problems.push_back(named(c) + " links to its own floor");
                continue;
            }
            const auto it = floors.find(l.floor_id);
            if (it == floors.end()) {
                problems.push_back(named(c) + " links to floor " + std::to_string(l.floor_id) + ", which is not a floor of this map");
                continue;
            }
            if (!it->second) continue;  // checked when that floor's plan arrives
            const Connector* other = find(*it->second, l.connector);
            if (!other) problems.push_back(named(c) + " links to " + to + ", which that floor's plan does not have");
            else if (!links_to(*other, floor_id, c.id)) problems.push_back(named(c) + " links to " + to + ", which does not link back");
        }
    }
    // What the other floors already say about this one must hold too.
    for (const auto& [other_floor, other] : floors) {
        if (!other) continue;
        for (const auto& oc : other->connectors)
            for (const auto& l : oc.links) {
                if (l.floor_id != floor_id) continue;
                const Connector* mine = find(plan, l.connector);
                const std::string from = "floor " + std::to_string(other_floor) + " connector '" + oc.id + "'";
                if (!mine) problems.push_back(from + " links to connector '" + l.connector + "' here, which this plan does not have");
                else if (!links_to(*mine, other_floor, oc.id))
                    problems.push_back(from + " links to " + named(*mine) + " here, which does not link back");
            }
    }
    return problems;
}

}  // namespace locus::plan
