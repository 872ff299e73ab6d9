#pragma once
// A plan drawn or exported on one floor, made fit for another (`locus plan import`): its
// spaces' room links, its connectors' POI links and its links to floors that the target floor
// does not know are dropped, so the server matches rooms by name on the target floor (as for
// a plan drawn by hand) and the plan is not refused for "room_id 1 is not a room of floor 3".
// Pure; O(size of the plan + the id sets).
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "locus/plan/plan.hpp"

namespace locus::tools {

// What the target floor has, as the server lists it.
struct FloorIds {
    std::int64_t floor_id = 0;
    std::set<std::int64_t> rooms, pois;
    std::set<std::int64_t> map_floors;  // every floor of its map, itself included
};

struct RemapReport {
    int room_links_kept = 0, room_links_dropped = 0;
    int poi_links_kept = 0, poi_links_dropped = 0;
    std::vector<std::string> floor_links_dropped;  // "connector 'S1' → floor 9": one line each
    bool changed() const { return room_links_dropped + poi_links_dropped > 0 || !floor_links_dropped.empty(); }
};

RemapReport remap_plan(plan::Plan& plan, const FloorIds& target);

}  // namespace locus::tools
