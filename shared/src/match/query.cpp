#include "locus/match/query.hpp"

#include <algorithm>
#include <functional>
#include <string_view>
#include <utility>

namespace locus::match {

namespace {
// Mean per (type, normalised bssid) in first-seen order; invalid RSS values are dropped.
// Duplicates are found by sorting rather than with a map: this runs for every localize
// request, and a map costs a node and two key copies per reading.
Query average(const std::vector<const Reading*>& readings) {
    Query q;
    q.aps.reserve(readings.size());
    for (const Reading* r : readings)
        if (valid_rss(r->rss)) q.aps.push_back(QueryAp{r->type, normalise_bssid(r->bssid), r->rss});
    // Repeats are found by sorting positions by (hash, key, position): strings are compared
    // only where hashes are equal, and within a key the first-seen reading comes first.
    const std::size_t n = q.aps.size();
    std::vector<std::size_t> hash(n), order(n);
    for (std::size_t i = 0; i < n; ++i) {
        hash[i] = std::hash<std::string_view>{}(q.aps[i].bssid);  // a type differs only in the key compare
        order[i] = i;
    }
    const auto key = [&](std::size_t i) { return std::pair<std::string_view, std::string_view>(q.aps[i].bssid, q.aps[i].type); };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (hash[a] != hash[b]) return hash[a] < hash[b];
        const auto ka = key(a), kb = key(b);
        return ka < kb || (ka == kb && a < b);
    });
    std::vector<bool> merged(n, false);
    for (std::size_t s = 0; s < n;) {
        std::size_t e = s + 1;
        while (e < n && hash[order[e]] == hash[order[s]] && key(order[e]) == key(order[s])) ++e;
        QueryAp& first = q.aps[order[s]];
        for (std::size_t j = s + 1; j < e; ++j) {
            first.rss += (q.aps[order[j]].rss - first.rss) / static_cast<double>(j - s + 1);
            merged[order[j]] = true;
        }
        s = e;
    }
    std::size_t w = 0;
    for (std::size_t i = 0; i < q.aps.size(); ++i)
        if (!merged[i]) {
            if (w != i) q.aps[w] = std::move(q.aps[i]);
            ++w;
        }
    q.aps.resize(w);
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
