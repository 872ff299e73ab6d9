#include "locus/match/query.hpp"

#include <algorithm>
#include <functional>
#include <string_view>
#include <utility>

namespace locus::match {

namespace {
// Mean per (type, normalised bssid) in first-seen order; invalid RSS values are dropped.
// Duplicates are found by sorting (hash, position) pairs rather than with a map: this runs
// for every localize request, and a map costs a node and two key copies per reading. Keys
// are compared only where hashes are equal; the scratch is per thread, so a warmed-up
// thread allocates nothing here but the query itself.
Query average(std::span<const ReadingView> readings) {
    Query q;
    q.aps.reserve(readings.size());
    for (const ReadingView& r : readings)
        if (valid_rss(r.rss)) q.aps.push_back(QueryAp{std::string(r.type), normalise_bssid(r.bssid), r.rss});
    struct Slot {
        std::size_t hash;
        std::size_t pos;
        double count;    // readings averaged into this one so far
        bool merged;     // averaged into an earlier reading of the same key
    };
    thread_local std::vector<Slot> slots;
    const std::size_t n = q.aps.size();
    slots.clear();
    for (std::size_t i = 0; i < n; ++i) {
        q.aps[i].bssid_hash = std::hash<std::string_view>{}(q.aps[i].bssid);
        slots.push_back(Slot{q.aps[i].bssid_hash, i, 1.0, false});  // a type differs only in the key compare
    }
    std::sort(slots.begin(), slots.end(),
              [](const Slot& a, const Slot& b) { return a.hash != b.hash ? a.hash < b.hash : a.pos < b.pos; });
    const auto same_key = [&](const Slot& a, const Slot& b) {
        return q.aps[a.pos].bssid == q.aps[b.pos].bssid && q.aps[a.pos].type == q.aps[b.pos].type;
    };
    bool any_merged = false;
    for (std::size_t s = 0; s < n;) {
        std::size_t e = s + 1;
        while (e < n && slots[e].hash == slots[s].hash) ++e;
        // Within one hash, in position order: each reading joins the first earlier one with
        // its key, so the mean is taken in first-seen order.
        for (std::size_t j = s + 1; j < e; ++j)
            for (std::size_t i = s; i < j; ++i) {
                Slot& first = slots[i];
                if (first.merged || !same_key(first, slots[j])) continue;
                first.count += 1.0;
                QueryAp& ap = q.aps[first.pos];
                ap.rss += (q.aps[slots[j].pos].rss - ap.rss) / first.count;
                slots[j].merged = any_merged = true;
                break;
            }
        s = e;
    }
    if (!any_merged) return q;
    thread_local std::vector<unsigned char> merged;
    merged.assign(n, 0);
    for (const Slot& slot : slots) merged[slot.pos] = slot.merged;
    std::size_t w = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (!merged[i]) {
            if (w != i) q.aps[w] = std::move(q.aps[i]);
            ++w;
        }
    q.aps.resize(w);
    return q;
}

void add_views(const std::vector<Reading>& readings, std::vector<ReadingView>& out) {
    for (const auto& r : readings) out.push_back(ReadingView{r.type, r.bssid, r.rss});
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
