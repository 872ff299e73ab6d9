#include "locus/match/query.hpp"

#include <map>
#include <utility>

namespace locus::match {

namespace {
// Mean per (type, normalised bssid) in first-seen order; invalid RSS values are dropped.
Query average(const std::vector<const Reading*>& readings) {
    Query q;
    std::map<std::pair<std::string, std::string>, std::size_t> slot;
    std::vector<int> counts;
    for (const Reading* r : readings) {
        if (!valid_rss(r->rss)) continue;
        auto key = std::make_pair(r->type, normalise_bssid(r->bssid));
        auto [it, inserted] = slot.try_emplace(key, q.aps.size());
        if (inserted) {
            q.aps.push_back(QueryAp{key.first, key.second, 0.0});
            counts.push_back(0);
        }
        const std::size_t i = it->second;
        ++counts[i];
        q.aps[i].rss += (r->rss - q.aps[i].rss) / counts[i];
    }
    return q;
}
}  // namespace

Query Query::from_scans(const std::vector<Scan>& scans) {
    std::vector<const Reading*> all;
    for (const auto& scan : scans)
        for (const auto& r : scan) all.push_back(&r);
    return average(all);
}

Query Query::from_means(const std::vector<Reading>& means) {
    std::vector<const Reading*> all;
    for (const auto& r : means) all.push_back(&r);
    return average(all);
}

}  // namespace locus::match
