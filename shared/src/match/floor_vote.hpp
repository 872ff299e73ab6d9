#pragma once
// Weight summed per (building, floor): the chosen RPs' vote on where a fix is, and bayes's
// vote before it picks its RPs. Few groups per query, so a linear search beats a map.
#include <algorithm>
#include <vector>

#include "locus/match/index.hpp"

namespace locus::match::detail {

class FloorVote {
public:
    struct Group {
        long long building, floor;
        double weight;
    };

    void add(const RpInfo& info, double w) {
        auto it = std::find_if(groups_.begin(), groups_.end(), [&](const Group& g) {
            return g.building == info.building_id && g.floor == info.floor_id;
        });
        if (it == groups_.end()) groups_.push_back(Group{info.building_id, info.floor_id, w});
        else it->weight += w;
    }
    // The most weight; on equal weight the group that got its first vote first, i.e. the
    // one holding the better-ranked RP when votes are cast in rank order.
    const Group& winner() const {
        const Group* g = &groups_.front();
        for (const auto& h : groups_)
            if (h.weight > g->weight) g = &h;
        return *g;
    }
    std::size_t size() const { return groups_.size(); }

private:
    std::vector<Group> groups_;
};

}  // namespace locus::match::detail
