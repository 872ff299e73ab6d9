#pragma once
// The one pass every matcher makes: the query's APs looked up in the index, then their
// posting lists walked into per-RP sums, then one Scored entry per RP that shares an AP.
// Templates, so each matcher's per-posting and per-RP code is inlined into its own loop.
#include <cassert>
#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "candidates.hpp"
#include "locus/match/index.hpp"
#include "locus/match/options.hpp"
#include "locus/match/query.hpp"
#include "locus/match/workspace.hpp"

namespace locus::match::detail {

struct Known {
    std::uint32_t ap;
    double rss;
    double rep;      // rss in the requested representation
    double penalty;  // bayes: log-likelihood of this AP at an RP that does not store it
};

// Totals over every online AP, known to the index or not: an AP the index has never seen
// is heard online only and still counts against every RP.
struct QueryTotals {
    double rep_sum = 0.0;
    double rep_sq_sum = 0.0;
    double penalty_sum = 0.0;
    double n_aps = 0.0;
};

// What a Workspace holds: per-query accumulators indexed by RP position, kept between
// queries so a query allocates nothing once warmed up. Between queries every per-RP slot is
// zero: only the RPs a query touched are reset afterwards, not the whole index.
struct Scratch {
    std::vector<int> shared;  // APs shared with the query; -1 = excluded by `near`
    std::vector<double> acc;  // the matcher's sum over the shared APs
    std::vector<double> acc_wd, acc_w;  // bayes device offset: Σ d/σ², Σ 1/σ²
    std::vector<double> acc_knn;        // bayes floor vote: the knn sum next to the likelihood
    std::vector<std::uint32_t> touched;
    std::vector<Known> known;
    std::vector<Scored> scored;
    std::vector<double> weights;
    std::vector<Scored> on_floor;  // bayes: the winning floor's candidates

    void clear();
};

// The workspace's scratch, sized for `index` and cleared.
Scratch& scratch_for(const Index& index, Workspace& workspace);

// Fills s.known with the query's APs the index knows, in query order. `penalty(rss)` is an
// AP's term at an RP that does not store it (bayes; 0 for the others).
template <typename Penalty>
QueryTotals prepare_query(const Index& index, const Query& query, int rep, Scratch& s, Penalty&& penalty) {
    QueryTotals q;
    q.n_aps = static_cast<double>(query.aps.size());
    s.known.clear();
    for (const auto& ap : query.aps) {
        const double r = index.represent(ap.rss, rep);
        const double p = penalty(ap.rss);
        q.rep_sum += r;
        q.rep_sq_sum += r * r;
        q.penalty_sum += p;
        // Only Query::from_scans/from_means make a QueryAp, and they set the hash.
        assert(ap.bssid_hash == std::hash<std::string_view>{}(ap.bssid));
        const long id = index.ap_of(ap.type, ap.bssid, ap.bssid_hash);
        if (id >= 0) s.known.push_back(Known{static_cast<std::uint32_t>(id), ap.rss, r, p});
    }
    return q;
}

inline bool outside(const Index& index, std::uint32_t rp, const Options& options) {
    return options.near && distance(index.rp(rp).at, options.near->at) > options.near->radius;
}

// One pass over the posting lists of the known APs, counting shared APs per RP and
// leaving out RPs beyond `near`; `f(known, list, j, rp)` adds one shared AP's term.
template <typename F>
void walk(const Index& index, const Options& options, Scratch& s, F&& f) {
    for (const auto& k : s.known) {
        const PostingList list = index.postings(k.ap);
        for (std::size_t j = 0; j < list.size(); ++j) {
            const std::uint32_t rp = list.rp[j];
            int& sh = s.shared[rp];
            if (sh == 0) {
                s.touched.push_back(rp);
                if (outside(index, rp, options)) sh = -1;
            }
            if (sh < 0) continue;
            ++sh;
            f(k, list, j, rp);
        }
    }
}

// One Scored per RP sharing an AP, in touch order; `score(sc, rp, acc)` sets its keys and
// score. Leaves the scratch's per-RP sums cleared.
template <typename Score>
std::vector<Scored>& collect(Scratch& s, Score&& score) {
    std::vector<Scored>& scored = s.scored;
    scored.clear();
    for (auto i : s.touched) {
        const int sh = s.shared[i];
        if (sh <= 0) continue;
        // Filled in place: a Scored built on the stack and then copied in stalled on its own
        // stores (a third of the matchers' time in the profile).
        Scored& sc = scored.emplace_back();
        sc.rp = i;
        sc.shared = sh;
        score(sc, i, s.acc[i]);
    }
    s.clear();
    return scored;
}

}  // namespace locus::match::detail
