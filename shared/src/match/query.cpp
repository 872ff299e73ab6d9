#include "locus/match/query.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <string_view>
#include <utility>

namespace locus::match {

namespace {
// Mean per (type, normalised bssid) in first-seen order; invalid RSS values are dropped.
// Duplicates are found by sorting (hash, key, position) slots rather than with a map: this
// runs for every localize request, and a map costs a node and two key copies per reading.
// Keys are compared only where hashes are equal, and the sort keeps the worst case at
// n log n even for readings chosen to share a hash.
Query average(std::span<const ReadingView> readings) {
    Query q;
    q.aps.reserve(readings.size());
    for (const ReadingView& r : readings)
        if (valid_rss(r.rss)) q.aps.push_back(QueryAp{std::string(r.type), r.normalised ? std::string(r.bssid) : Bssid(r.bssid).str(), r.rss});
    struct Slot {
        std::size_t hash;
        std::size_t pos;
    };
    // A scan hears tens of APs: its slots fit on the stack, so the usual query allocates
    // nothing here but itself and the core keeps no scratch between calls. Only a longer
    // list takes its slots from the heap.
    constexpr std::size_t kOnStack = 256;
    std::array<Slot, kOnStack> on_stack;
    std::vector<Slot> on_heap;
    const std::size_t n = q.aps.size();
    if (n > kOnStack) on_heap.resize(n);
    Slot* const slots = n > kOnStack ? on_heap.data() : on_stack.data();
    for (std::size_t i = 0; i < n; ++i) {
        q.aps[i].bssid_hash = std::hash<std::string_view>{}(q.aps[i].bssid);
        slots[i] = Slot{q.aps[i].bssid_hash, i};  // a type differs only in the key compare
    }
    const auto key = [&](const Slot& a) {
        return std::pair<std::string_view, std::string_view>(q.aps[a.pos].bssid, q.aps[a.pos].type);
    };
    std::sort(slots, slots + n, [&](const Slot& a, const Slot& b) {
        if (a.hash != b.hash) return a.hash < b.hash;
        const auto ka = key(a), kb = key(b);
        return ka != kb ? ka < kb : a.pos < b.pos;
    });
    // Within a key the first-seen reading comes first: the later ones are averaged into it
    // in the order they were seen. A reading averaged away is marked by a NaN RSS, which no
    // kept reading can have (valid_rss dropped them all above).
    bool any_merged = false;
    for (std::size_t s = 0; s < n;) {
        std::size_t e = s + 1;
        QueryAp& first = q.aps[slots[s].pos];
        for (; e < n && slots[e].hash == slots[s].hash && key(slots[e]) == key(slots[s]); ++e) {
            double& rss = q.aps[slots[e].pos].rss;
            first.rss += (rss - first.rss) / static_cast<double>(e - s + 1);
            rss = std::numeric_limits<double>::quiet_NaN();
            any_merged = true;
        }
        s = e;
    }
    if (any_merged) {
        std::size_t w = 0;
        for (std::size_t i = 0; i < n; ++i)
            if (!std::isnan(q.aps[i].rss)) {
                if (w != i) q.aps[w] = std::move(q.aps[i]);
                ++w;
            }
        q.aps.resize(w);
    }
    return q;
}

void add_views(const std::vector<Reading>& readings, std::vector<ReadingView>& out) {
    for (const auto& r : readings) out.push_back(ReadingView{r.type, r.bssid.str(), r.rss, true});
}

}  // namespace

Query Query::from_scans(const std::vector<Scan>& scans) {
    std::vector<ReadingView> all;
    for (const auto& scan : scans) add_views(scan, all);
    return average(all);
}

Query Query::from_means(const std::vector<Reading>& means) {
    std::vector<ReadingView> all;
    add_views(means, all);
    return average(all);
}

Query Query::from_means(std::span<const ReadingView> means) { return average(means); }

}  // namespace locus::match
