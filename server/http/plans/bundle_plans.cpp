#include "http/plans/bundle_plans.hpp"

#include <map>
#include <string>

#include "http/api_error.hpp"
#include "http/plans/plan_json.hpp"
#include "http/plans/plan_put.hpp"
#include "store/kinds.hpp"

namespace locus::http {

using nlohmann::json;

std::vector<BundlePlan> parse_bundle_plans(const json& bundle) {
    std::vector<BundlePlan> out;
    if (!bundle.is_object() || !bundle.contains("buildings") || !bundle.at("buildings").is_array()) return out;
    const json& buildings = bundle.at("buildings");
    for (std::size_t i = 0; i < buildings.size(); ++i) {
        if (!buildings[i].is_object() || !buildings[i].contains("floors") || !buildings[i].at("floors").is_array()) continue;
        const json& floors = buildings[i].at("floors");
        for (std::size_t j = 0; j < floors.size(); ++j) {
            const json& floor = floors[j];
            if (!floor.is_object() || !floor.contains("plan")) continue;
            BundlePlan bp;
            bp.building = i;
            bp.where = "buildings[" + std::to_string(i) + "].floors[" + std::to_string(j) + "].plan";
            if (!floor.contains("level") || !floor.at("level").is_number_integer())
                throw invalid_field("'" + bp.where + "' needs its floor's integer 'level'");
            bp.level = floor.at("level").get<std::int64_t>();
            // Links by level become links to a placeholder floor id for the codec, which
            // checks everything else about them; the levels are kept beside.
            json doc = floor.at("plan");
            if (doc.is_object() && doc.contains("features") && doc.at("features").is_array())
                for (std::size_t k = 0; k < doc.at("features").size(); ++k) {
                    json& f = doc.at("features")[k];
                    if (!f.is_object() || !f.contains("properties") || !f.at("properties").is_object()) continue;
                    json& props = f.at("properties");
                    if (props.value("feature", "") != "connector") continue;
                    std::vector<std::int64_t> levels;
                    if (props.contains("links") && props.at("links").is_array())
                        for (auto& link : props.at("links")) {
                            if (!link.is_object() || !link.contains("level") || !link.at("level").is_number_integer())
                                throw invalid_field("'" + bp.where + ".features[" + std::to_string(k) +
                                                    "]': a bundle's links are {\"level\": L, \"connector\": ID}");
                            levels.push_back(link.at("level").get<std::int64_t>());
                            link.erase("level");
                            link["floor_id"] = 1;
                        }
                    bp.link_levels.push_back(std::move(levels));
                }
            try {
                bp.plan = parse_plan(doc);
            } catch (const ApiError& e) {
                throw ApiError(e.status, e.code, bp.where + ": " + e.what());
            }
            out.push_back(std::move(bp));
        }
    }
    return out;
}

void put_bundle_plans(store::Store& store, std::int64_t map_id, const std::vector<BundlePlan>& plans) {
    const auto buildings = store.list(store::kind("buildings"), map_id, 1000, 0).items;
    for (const auto& bp : plans) {
        if (bp.building >= buildings.size()) throw invalid_field("'" + bp.where + "': no such building in map " + std::to_string(map_id));
        std::map<std::int64_t, std::int64_t> floor_of_level;
        for (const auto& f : store.list(store::kind("floors"), buildings[bp.building].id, 1000, 0).items)
            floor_of_level.emplace(f.fields.get<std::int64_t>("level"), f.id);
        auto floor_at = [&](std::int64_t level) {
            const auto it = floor_of_level.find(level);
            if (it == floor_of_level.end())
                throw invalid_field("'" + bp.where + "': the building has no floor at level " + std::to_string(level));
            return it->second;
        };
        plan::Plan p = bp.plan;
        for (std::size_t k = 0; k < p.connectors.size() && k < bp.link_levels.size(); ++k)
            for (std::size_t j = 0; j < p.connectors[k].links.size() && j < bp.link_levels[k].size(); ++j)
                p.connectors[k].links[j].floor_id = floor_at(bp.link_levels[k][j]);
        try {
            put_checked_plan(store, floor_at(bp.level), p);
        } catch (const ApiError& e) {
            throw ApiError(e.status, e.code, bp.where + ": " + e.what());
        }
    }
}

}  // namespace locus::http
