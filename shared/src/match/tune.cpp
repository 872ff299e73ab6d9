#include "locus/match/tune.hpp"

#include "locus/match/quality.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>

#include "locus/geometry.hpp"
#include "locus/match/localize.hpp"
#include "locus/match/query.hpp"

namespace locus::match {

namespace {

TuneCandidate candidate(Algorithm a, int k, Representation r = Representation::powed, Distance d = Distance::sorensen) {
    TuneCandidate c;
    c.setting.algorithm = a;
    c.setting.options.k = k;
    c.setting.options.representation = r;
    c.setting.options.distance = d;
    // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on a chain of operator+.
    c.name.append(to_string(a)).append(" k=").append(std::to_string(k));
    if (a != Algorithm::bayes) c.name.append(" ").append(to_string(r)).append(" ").append(to_string(d));
    return c;
}

// A fixed-seed Fisher–Yates shuffle written out (std::shuffle's steps are up to the library),
// so the folds, and so the choice, are the same on every platform.
std::vector<std::size_t> shuffled(std::size_t n) {
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    std::mt19937_64 rng(0x10c05u);
    for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng() % i]);
    return order;
}

Query query_of(const ReferencePoint& rp) {
    std::vector<Reading> means;
    means.reserve(rp.measurements.size());
    for (const auto& m : rp.measurements) means.push_back(Reading{m.type, m.bssid, m.stats.mean});
    return Query::from_means(means);
}

}  // namespace

std::vector<TuneCandidate> tune_grid() {
    std::vector<TuneCandidate> grid;
    grid.push_back({"bayes (built-in default)", Setting{}});
    TuneCandidate wide{"bayes bayes_k=20", Setting{}};
    wide.setting.options.bayes_k = 20;
    grid.push_back(wide);
    // The hybrid: bayes places the fix, the knn vote of the 5 nearest RPs helps name its
    // floor (a third of the floor vote) without moving it (docs/matchers.md, phase 3).
    TuneCandidate hybrid{"bayes bayes_k=20 floor_knn=5 w=0.3 floor only", Setting{}};
    hybrid.setting.options.bayes_k = 20;
    hybrid.setting.options.floor_knn = 5;
    hybrid.setting.options.floor_knn_weight = 0.3;
    hybrid.setting.options.floor_knn_position = false;
    grid.push_back(hybrid);
    for (int k : {3, 5, 8}) grid.push_back(candidate(Algorithm::wknn, k));
    grid.push_back(candidate(Algorithm::wknn, 3, Representation::exponential));
    grid.push_back(candidate(Algorithm::wknn, 3, Representation::positive, Distance::euclidean));
    for (int k : {1, 3}) grid.push_back(candidate(Algorithm::knn, k));
    return grid;
}

// The folds tune and held_out_errors share: position i of the shuffled order is in fold
// i % folds, or, with TuneLimits::blocks, in its block's fold; of the held-out RPs only those
// among the first `queried` of the shuffled order are localized (the subsample). visit(index,
// h, query) runs for each held-out RP h that holds a measurement, against the index of the
// other folds' RPs (added in shuffled order either way).
struct Folds {
    std::size_t folds = 0, queried = 0;
};

// Per RP, its fold by the limits' blocks; empty when there are none or they leave fewer than
// 2 folds holding RPs.
std::vector<int> block_folds(const std::vector<IndexedRp>& rps, std::size_t folds, const TuneLimits& limits) {
    if (!limits.blocks) return {};
    std::vector<FoldSite> sites;
    sites.reserve(rps.size());
    for (const auto& r : rps) sites.push_back({r.building_id, r.floor_id, r.rp.at});
    auto fold_of = assign_folds(sites, static_cast<int>(folds), *limits.blocks);
    const bool split = std::any_of(fold_of.begin(), fold_of.end(), [&fold_of](int f) { return f != fold_of.front(); });
    if (!split) fold_of.clear();
    return fold_of;
}

template <class Visit>
Folds for_each_held_out(const std::vector<IndexedRp>& rps, const TuneLimits& limits, const IndexParams& params, Visit visit) {
    const std::size_t n = rps.size();
    const std::size_t folds = std::clamp<std::size_t>(static_cast<std::size_t>(std::max(limits.folds, 2)), 2, n);
    const auto order = shuffled(n);
    const auto blocked = block_folds(rps, folds, limits);
    const std::size_t queried = std::min(n, std::max<std::size_t>(limits.max_queries, 1));
    std::vector<IndexedRp> kept;
    kept.reserve(n);
    for (std::size_t f = 0; f < folds; ++f) {
        std::vector<std::size_t> held;
        kept.clear();
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t fold = blocked.empty() ? i % folds : static_cast<std::size_t>(blocked[order[i]]);
            if (fold == f) {
                if (i < queried) held.push_back(order[i]);
            } else {
                kept.push_back(rps[order[i]]);
            }
        }
        if (held.empty() || kept.empty()) continue;
        const Index index = Index::build(kept, params);
        for (const auto h : held) {
            const Query q = query_of(rps[h].rp);
            if (q.aps.empty()) continue;  // an RP with no measurement is no scan
            visit(index, h, q);
        }
    }
    return {folds, queried};
}

TuneReport tune(const std::vector<IndexedRp>& rps, std::span<const TuneCandidate> grid, const FloorLevel& level_of,
                const TuneLimits& limits, const IndexParams& params) {
    if (rps.size() < 2)
        throw TuneRefused("a radio map needs at least 2 RPs to be tuned (it has " + std::to_string(rps.size()) +
                          "): each RP is localized against the others");
    if (grid.empty()) throw TuneRefused("no candidate settings to compare");
    const std::size_t n = rps.size();
    struct Sums {
        double evaal = 0.0, horizontal = 0.0;
        std::size_t answered = 0, floor_hits = 0, building_hits = 0, unanswered = 0;
    };
    std::vector<Sums> sums(grid.size());
    std::size_t queries = 0;
    Workspace workspace;
    const Folds f = for_each_held_out(rps, limits, params, [&](const Index& index, std::size_t h, const Query& q) {
        const auto& truth = rps[h];
        ++queries;
        for (std::size_t c = 0; c < grid.size(); ++c) {
            auto& s = sums[c];
            const auto r = localize(index, q, grid[c].setting.algorithm, grid[c].setting.options, workspace);
            if (!r) {
                ++s.unanswered;
                s.evaal += kBuildingPenaltyM;
                continue;
            }
            const double e = distance(r->at, truth.rp.at);
            const bool building_ok = r->building_id == truth.building_id;
            const bool floor_ok = building_ok && r->floor_id == truth.floor_id;
            ++s.answered;
            s.horizontal += e;
            s.building_hits += building_ok;
            s.floor_hits += floor_ok;
            double floors = 0.0;
            if (!floor_ok)
                floors = static_cast<double>(std::llabs(level_of(r->floor_id) - level_of(truth.floor_id)));
            s.evaal += e + kFloorPenaltyM * floors + (building_ok ? 0.0 : kBuildingPenaltyM);
        }
    });
    TuneReport report;
    report.rps = n;
    report.folds = f.folds;
    report.queries = queries;
    report.subsampled = f.queried < n;
    const double nq = queries > 0 ? static_cast<double>(queries) : 1.0;
    for (std::size_t c = 0; c < grid.size(); ++c) {
        const auto& s = sums[c];
        TuneRow row;
        row.name = grid[c].name;
        row.setting = grid[c].setting;
        row.mean_error_m = s.evaal / nq;
        row.mean_horizontal_m = s.answered > 0 ? s.horizontal / static_cast<double>(s.answered) : 0.0;
        row.floor_hit_rate = static_cast<double>(s.floor_hits) / nq;
        row.building_hit_rate = static_cast<double>(s.building_hits) / nq;
        row.unanswered = s.unanswered;
        if (c > 0 && row.mean_error_m < report.rows[report.best].mean_error_m) report.best = c;
        report.rows.push_back(std::move(row));
    }
    if (queries == 0) throw TuneRefused("no RP of the radio map holds a measurement to localize");
    return report;
}

// In this file beside tune: the same folds and the same scans, so the layer shows the errors
// tune's table averages for the chosen setting.
QualityReport held_out_errors(const std::vector<IndexedRp>& rps, const Setting& setting, const FloorLevel& level_of,
                              const TuneLimits& limits, const IndexParams& params) {
    if (rps.size() < 2)
        throw TuneRefused("a radio map needs at least 2 RPs (it has " + std::to_string(rps.size()) +
                          "): each RP is localized against the others");
    const std::size_t n = rps.size();
    QualityReport report;
    report.rps.resize(n);
    for (std::size_t i = 0; i < n; ++i) report.rps[i].rp = i;
    Workspace workspace;
    const Folds f = for_each_held_out(rps, limits, params, [&](const Index& index, std::size_t h, const Query& q) {
        const auto& truth = rps[h];
        ++report.queries;
        auto& out = report.rps[h];
        const auto r = localize(index, q, setting.algorithm, setting.options, workspace);
        if (!r) {
            out.error_m = kBuildingPenaltyM;
            return;
        }
        const double e = distance(r->at, truth.rp.at);
        const bool building_ok = r->building_id == truth.building_id;
        out.floor_ok = building_ok && r->floor_id == truth.floor_id;
        const double floors = out.floor_ok ? 0.0 : static_cast<double>(std::llabs(level_of(r->floor_id) - level_of(truth.floor_id)));
        out.horizontal_m = e;
        out.error_m = e + kFloorPenaltyM * floors + (building_ok ? 0.0 : kBuildingPenaltyM);
    });
    report.folds = f.folds;
    report.subsampled = f.queried < n;
    if (report.queries == 0) throw TuneRefused("no RP of the radio map holds a measurement to localize");
    return report;
}

}  // namespace locus::match
