#include "estimate.hpp"

#include <algorithm>
#include <string>

#include "floor_vote.hpp"

namespace locus::match::detail {

Result estimate(const Index& index, Algorithm algorithm, const std::vector<Scored>& ranked, const Chosen& chosen,
                std::size_t n_listed, const Options& options) {
    // Only the winning floor's RPs make the position (unless the options say otherwise), so
    // a fix never averages points on different floors.
    FloorVote vote;
    for (const auto& c : chosen) vote.add(index.rp(c.scored->rp), c.weight);
    const FloorVote::Group& win = vote.winner();

    const Scored& best = ranked.front();
    Result result;
    result.algorithm = std::string(to_string(algorithm));
    result.building_id = win.building;
    result.floor_id = win.floor;
    result.score = best.score;
    result.matched_aps = best.shared;
    double wsum = 0.0, x = 0.0, y = 0.0;
    for (const auto& c : chosen) {
        const RpInfo& info = index.rp(c.scored->rp);
        if (options.position_on_voted_floor && (info.building_id != win.building || info.floor_id != win.floor))
            continue;
        result.rp_ids.push_back(info.id);
        wsum += c.weight;
        x += c.weight * info.at.x;
        y += c.weight * info.at.y;
    }
    result.at = Point{x / wsum, y / wsum};

    const std::size_t n_candidates = std::min(n_listed, static_cast<std::size_t>(std::max(0, options.candidates)));
    for (std::size_t j = 0; j < n_candidates; ++j) {
        const Scored& c = ranked[j];
        const RpInfo& info = index.rp(c.rp);
        result.candidates.push_back(Candidate{info.id, info.at, c.score, info.floor_id, info.building_id, c.shared});
    }
    return result;
}

}  // namespace locus::match::detail
