#include "plan_remap.hpp"

#include <algorithm>

namespace locus::tools {

RemapReport remap_plan(plan::Plan& plan, const FloorIds& target) {
    RemapReport report;
    for (auto& space : plan.spaces) {
        if (!space.room_id) continue;
        if (target.rooms.count(*space.room_id)) {
            ++report.room_links_kept;
        } else {
            space.room_id.reset();
            ++report.room_links_dropped;
        }
    }
    for (auto& c : plan.connectors) {
        if (c.poi_id) {
            if (target.pois.count(*c.poi_id)) {
                ++report.poi_links_kept;
            } else {
                c.poi_id.reset();
                ++report.poi_links_dropped;
            }
        }
        const auto gone = [&](const plan::ConnectorLink& l) {
            return l.floor_id == target.floor_id || !target.map_floors.count(l.floor_id);
        };
        for (const auto& l : c.links)
            if (gone(l)) report.floor_links_dropped.push_back("connector '" + c.id + "' → floor " + std::to_string(l.floor_id));
        c.links.erase(std::remove_if(c.links.begin(), c.links.end(), gone), c.links.end());
    }
    return report;
}

}  // namespace locus::tools
