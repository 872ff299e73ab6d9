#include "locus/match/localize.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace locus::match {

namespace {

// Lower key1, then lower key2, then lower RP position ranks first.
struct Scored {
    std::uint32_t rp;
    double key1;
    double key2;
    double score;  // what the caller sees
    int shared;
    double aux = 0.0;  // bayes with floor_knn: the RP's knn distance to the query
};

// A function object rather than a function, so the sorts inline the comparison.
constexpr auto better = [](const Scored& a, const Scored& b) {
    if (a.key1 != b.key1) return a.key1 < b.key1;
    if (a.key2 != b.key2) return a.key2 < b.key2;
    return a.rp < b.rp;
};

constexpr double kLog2Pi = 1.8378770664093453;  // log(2π)

struct Known {
    std::uint32_t ap;
    double rss;
    double rep;      // rss in the requested representation
    double penalty;  // bayes: log-likelihood of this AP at an RP that does not store it
};

bool within_tolerance(double value, double best, double tolerance) {
    return std::abs(value - best) <= tolerance * std::abs(best);
}

// Per-query accumulators indexed by RP position. Thread-local so concurrent queries on
// one Index never share them and a query allocates nothing once warmed up; only the RPs a
// query touched are reset afterwards.
struct Scratch {
    std::vector<int> shared;    // APs shared with the query; -1 = excluded by `near`
    std::vector<double> acc;    // algorithm-specific sum over the shared APs
    std::vector<double> acc_wd, acc_w;  // bayes device offset: Σ d/σ², Σ 1/σ²
    std::vector<double> acc_knn;        // bayes floor vote: the knn sum next to the likelihood
    std::vector<std::uint32_t> touched;
    std::vector<Known> known;
    std::vector<Scored> scored;
    std::vector<double> weights;

    void prepare(std::size_t n) {
        if (shared.size() < n) {
            shared.resize(n, 0);
            acc.resize(n, 0.0);
            acc_wd.resize(n, 0.0);
            acc_w.resize(n, 0.0);
            acc_knn.resize(n, 0.0);
        }
    }
    void clear() {
        for (auto i : touched) {
            shared[i] = 0;
            acc[i] = 0.0;
            acc_wd[i] = 0.0;
            acc_w[i] = 0.0;
            acc_knn[i] = 0.0;
        }
        touched.clear();
    }
};

thread_local Scratch t_scratch;

}  // namespace

std::optional<Result> localize(const Index& index, const Query& query, Algorithm algorithm, const Options& options) {
    const int rep = static_cast<int>(options.representation);
    const IndexParams& params = index.params();
    // A zero floor would divide by the zero variance of an AP sampled once.
    const double sigma_floor = std::max(options.sigma_floor, 0.1);
    const double sigma2_floor = sigma_floor * sigma_floor;
    const double log_sigma2_floor = std::log(sigma2_floor);
    const double n_online = static_cast<double>(query.aps.size());
    // bayes: no AP's squared standardised residual counts beyond κ², so one glitched
    // reading (phones report 0 dBm for APs heard at -80 elsewhere) cannot outweigh the rest.
    const double kappa2 = options.outlier_sigmas > 0.0 ? options.outlier_sigmas * options.outlier_sigmas
                                                       : std::numeric_limits<double>::infinity();

    // Query-side totals over every online AP, known to the index or not (an AP the index
    // has never seen is heard online only and still counts against every RP).
    double q_sum = 0.0, q_sq_sum = 0.0, q_penalty = 0.0;
    Scratch& s = t_scratch;
    std::vector<Known>& known = s.known;
    known.clear();
    const bool bayes = algorithm == Algorithm::bayes;
    const double penalty_base = bayes ? std::log(params.min_detection) - 0.5 * (kLog2Pi + log_sigma2_floor) : 0.0;
    for (const auto& ap : query.aps) {
        const double r = index.represent(ap.rss, rep);
        const double d = ap.rss - params.missing_rss;
        // An AP the RP does not store: as if it were stored with the missing value, the
        // floored variance and the minimum detection rate.
        const double penalty = bayes ? penalty_base - 0.5 * std::min(d * d / sigma2_floor, kappa2) : 0.0;
        q_sum += r;
        q_sq_sum += r * r;
        q_penalty += penalty;
        // Only Query::from_scans/from_means make a QueryAp, and they set the hash.
        assert(ap.bssid_hash == std::hash<std::string_view>{}(ap.bssid));
        const long id = index.ap_of(ap.type, ap.bssid, ap.bssid_hash);
        if (id >= 0) known.push_back(Known{static_cast<std::uint32_t>(id), ap.rss, r, penalty});
    }

    s.prepare(index.size());
    s.clear();
    const bool euclid = options.distance == Distance::euclidean;
    // The knn term of one shared AP: the correction from "each side heard alone" to "both
    // heard" for this AP.
    auto knn_term = [euclid](double a, double b) { return euclid ? a * b : std::abs(a - b) - a - b; };
    // Distance over the union of APs from the shared-AP sum `acc` and the precomputed totals.
    auto knn_distance = [&](std::uint32_t i, double acc) {
        if (euclid) return std::sqrt(std::max(0.0, index.rep_sq_sum(i, rep) + q_sq_sum - 2.0 * acc));
        const double manhattan = std::max(0.0, index.rep_sum(i, rep) + q_sum + acc);
        if (options.distance == Distance::manhattan) return manhattan;
        const double total = index.rep_sum(i, rep) + q_sum;
        return total > 0.0 ? manhattan / total : 1.0;
    };
    const bool floor_knn = algorithm == Algorithm::bayes && options.floor_knn > 0;
    // One pass over the posting lists of the query's APs; `f` adds one shared AP's term.
    // A template per algorithm keeps the inner loop free of dispatch.
    auto walk = [&](auto&& f) {
        for (const auto& k : known) {
            const PostingList list = index.postings(k.ap);
            for (std::size_t j = 0; j < list.size(); ++j) {
                const std::uint32_t rp = list.rp[j];
                int& sh = s.shared[rp];
                if (sh == 0) {
                    s.touched.push_back(rp);
                    if (options.near && distance(index.rp(rp).at, options.near->at) > options.near->radius) sh = -1;
                }
                if (sh < 0) continue;
                ++sh;
                f(k, list, j, rp);
            }
        }
    };
    switch (algorithm) {
        case Algorithm::bsb:
            walk([](const Known&, const PostingList&, std::size_t, std::uint32_t) {});
            break;
        case Algorithm::nn:
        case Algorithm::bsbnn:
            walk([&](const Known& k, const PostingList& list, std::size_t j, std::uint32_t rp) {
                const double d = list.mean[j] - k.rss;
                s.acc[rp] += d * d;
            });
            break;
        case Algorithm::knn:
        case Algorithm::wknn:
            walk([&](const Known& k, const PostingList& list, std::size_t j, std::uint32_t rp) {
                s.acc[rp] += knn_term(list.rep[rep][j], k.rep);
            });
            break;
        case Algorithm::bayes: {
            auto gauss = [&](const Known& k, const PostingList& list, std::size_t j, std::uint32_t rp) {
                const LikelihoodTerms& t = list.likelihood[j];
                const bool floored = t.variance < sigma2_floor;
                const double var = floored ? sigma2_floor : t.variance;
                const double log_var = floored ? log_sigma2_floor : t.log_variance;
                const double d = k.rss - list.mean[j];
                const double inv = 1.0 / var;
                const double z2 = d * d * inv;
                const double log_gauss = -0.5 * (kLog2Pi + log_var) - 0.5 * std::min(z2, kappa2);
                s.acc[rp] += t.log_detect + log_gauss - t.log_miss - k.penalty;
                // A capped reading says nothing about the phone's offset either.
                const double inv_var = z2 > kappa2 ? 0.0 : inv;
                s.acc_wd[rp] += d * inv_var;
                s.acc_w[rp] += inv_var;
            };
            if (floor_knn) {
                walk([&](const Known& k, const PostingList& list, std::size_t j, std::uint32_t rp) {
                    gauss(k, list, j, rp);
                    s.acc_knn[rp] += knn_term(list.rep[rep][j], k.rep);
                });
            } else {
                walk(gauss);
            }
            break;
        }
    }

    std::vector<Scored>& scored = s.scored;
    scored.clear();
    for (auto i : s.touched) {
        const int sh = s.shared[i];
        if (sh <= 0) continue;
        const double acc = s.acc[i];
        // Filled in place: a Scored built on the stack and then copied in stalled on its own
        // stores (a third of this function's time in the profile).
        Scored& sc = scored.emplace_back();
        sc.rp = i;
        sc.shared = sh;
        switch (algorithm) {
            case Algorithm::bsb:
                sc.key1 = -sh;
                sc.score = sh;
                break;
            case Algorithm::nn:
            case Algorithm::bsbnn: {
                const double extra = std::max(0.0, static_cast<double>(index.rp(i).ap_count) - n_online);
                const double nn = std::sqrt(acc) + options.gamma * extra;
                sc.key1 = algorithm == Algorithm::nn ? nn : -sh;
                sc.key2 = algorithm == Algorithm::nn ? 0.0 : nn;
                sc.score = nn;
                break;
            }
            case Algorithm::knn:
            case Algorithm::wknn: {
                const double d = knn_distance(i, acc);
                sc.key1 = d;
                sc.score = d;
                break;
            }
            case Algorithm::bayes: {
                double ll = q_penalty + index.log_miss_sum(i) + acc;
                // Phones disagree on RSS by a near-constant offset δ: the best δ for this RP
                // under a N(0, offset_sigma²) prior, in closed form, and the Gaussian terms'
                // gain from using it.
                if (options.offset_sigma > 0.0) {
                    const double wd = s.acc_wd[i];
                    ll += 0.5 * wd * wd / (s.acc_w[i] + 1.0 / (options.offset_sigma * options.offset_sigma));
                }
                sc.key1 = -ll;
                sc.score = ll;
                if (floor_knn) sc.aux = knn_distance(i, s.acc_knn[i]);
                break;
            }
        }
    }
    s.clear();
    if (scored.empty()) return std::nullopt;

    const int k = std::max(1, algorithm == Algorithm::bayes && options.bayes_k > 0 ? options.bayes_k : options.k);
    const bool top_k = algorithm == Algorithm::knn || algorithm == Algorithm::wknn ||
                       (algorithm == Algorithm::bayes && options.estimate == BayesEstimate::mean);
    const std::size_t n_listed = std::min(scored.size(), static_cast<std::size_t>(std::max({options.candidates, k, 1})));
    std::partial_sort(scored.begin(), scored.begin() + static_cast<long>(n_listed), scored.end(), better);
    const Scored best = scored.front();

    struct Group {
        long long building, floor;
        double weight;
    };
    std::vector<Group> groups;
    auto add_to_group = [&](std::uint32_t rp, double w) {
        const RpInfo& info = index.rp(rp);
        auto it = std::find_if(groups.begin(), groups.end(),
                               [&](const Group& g) { return g.building == info.building_id && g.floor == info.floor_id; });
        if (it == groups.end()) groups.push_back(Group{info.building_id, info.floor_id, w});
        else it->weight += w;
    };
    const double temperature = std::max(options.temperature, 1e-9);
    auto posterior = [&](const Scored& c) { return std::exp((best.key1 - c.key1) / temperature); };

    // Bayes picks the floor first, by posterior mass over every candidate RP (and, with
    // floor_knn, the knn vote of the nearest RPs), then builds the position from that
    // floor's RPs only.
    std::vector<Scored> on_floor;
    const std::vector<Scored>* pool = &scored;
    if (algorithm == Algorithm::bayes) {
        const double floor_t = options.floor_temperature > 0.0 ? options.floor_temperature : temperature;
        const double knn_w = floor_knn ? std::clamp(options.floor_knn_weight, 0.0, 1.0) : 0.0;
        const double ap_w = options.floor_aps > 0 ? std::clamp(options.floor_ap_weight, 0.0, 1.0 - knn_w) : 0.0;
        std::vector<double>& mass_of = s.weights;  // each candidate's unnormalised posterior
        mass_of.clear();
        double mass = 0.0;
        for (const auto& c : scored) mass += mass_of.emplace_back(std::exp((best.key1 - c.key1) / floor_t));
        for (std::size_t j = 0; j < scored.size(); ++j) add_to_group(scored[j].rp, (1.0 - knn_w - ap_w) * mass_of[j] / mass);
        if (ap_w > 0.0) {
            // The strongest APs first; an AP whose home RP lies outside `near` does not vote,
            // so the winning floor always has candidates.
            std::vector<Known>& loudest = known;  // not read after this point
            const std::size_t n = std::min(loudest.size(), static_cast<std::size_t>(options.floor_aps));
            std::partial_sort(loudest.begin(), loudest.begin() + static_cast<long>(n), loudest.end(),
                              [](const Known& a, const Known& b) { return a.rss != b.rss ? a.rss > b.rss : a.ap < b.ap; });
            for (std::size_t j = 0; j < n; ++j) {
                const std::uint32_t home = index.strongest_rp(loudest[j].ap);
                if (options.near && distance(index.rp(home).at, options.near->at) > options.near->radius) continue;
                add_to_group(home, ap_w / static_cast<double>(n));
            }
        }
        if (floor_knn) {
            std::vector<Scored>& near_rps = on_floor;  // reused as scratch, cleared below
            near_rps.assign(scored.begin(), scored.end());
            const std::size_t n = std::min(near_rps.size(), static_cast<std::size_t>(options.floor_knn));
            auto closer = [](const Scored& a, const Scored& b) { return a.aux != b.aux ? a.aux < b.aux : a.rp < b.rp; };
            std::partial_sort(near_rps.begin(), near_rps.begin() + static_cast<long>(n), near_rps.end(), closer);
            for (std::size_t j = 0; j < n; ++j) add_to_group(near_rps[j].rp, knn_w / static_cast<double>(n));
            on_floor.clear();
        }
        const Group* g = &groups.front();
        for (const auto& h : groups)
            if (h.weight > g->weight) g = &h;
        // One group means every candidate is on that floor (a radio map's index, or a map
        // heard on one floor only), and `scored` is already that floor's list, sorted.
        if (groups.size() > 1) {
            for (const auto& c : scored) {
                const RpInfo& info = index.rp(c.rp);
                if (info.building_id == g->building && info.floor_id == g->floor) on_floor.push_back(c);
            }
            const std::size_t n = std::min(on_floor.size(), n_listed);
            std::partial_sort(on_floor.begin(), on_floor.begin() + static_cast<long>(n), on_floor.end(), better);
            pool = &on_floor;
        }
        groups.clear();
    }

    // The set the answer is built from, best first, with a weight each.
    std::vector<std::pair<const Scored*, double>> chosen;
    const Scored& pool_best = pool->front();
    if (top_k) {
        const std::size_t n = std::min(pool->size(), static_cast<std::size_t>(k));
        for (std::size_t j = 0; j < n; ++j) {
            const Scored& c = (*pool)[j];
            double w = 1.0;
            if (algorithm == Algorithm::wknn) w = 1.0 / std::max(c.key1, 1e-9);
            if (algorithm == Algorithm::bayes) w = posterior(c);
            chosen.emplace_back(&c, w);
        }
    } else {
        // Every RP tied with (or, with a tolerance, close to) the best, in rank order: the
        // listed prefix is sorted; anything beyond it is sorted here.
        std::vector<const Scored*> set;
        for (const auto& c : *pool) {
            const bool in = algorithm == Algorithm::bsbnn
                                ? c.key1 == pool_best.key1 && within_tolerance(c.key2, pool_best.key2, options.tolerance)
                                : within_tolerance(c.key1, pool_best.key1, options.tolerance);
            if (in) set.push_back(&c);
        }
        std::sort(set.begin(), set.end(), [](const Scored* a, const Scored* b) { return better(*a, *b); });
        for (const Scored* c : set) chosen.emplace_back(c, 1.0);
    }

    // Building and floor: the (building, floor) carrying the most weight in the chosen set;
    // on equal weight, the one holding the better-ranked RP. Only that floor's RPs make the
    // position, so a fix never averages points on different floors.
    for (const auto& [c, w] : chosen) add_to_group(c->rp, w);
    const Group* win = &groups.front();
    for (const auto& g : groups)
        if (g.weight > win->weight) win = &g;

    Result result;
    result.algorithm = std::string(to_string(algorithm));
    result.building_id = win->building;
    result.floor_id = win->floor;
    result.score = best.score;
    result.matched_aps = best.shared;
    double wsum = 0.0, x = 0.0, y = 0.0;
    for (const auto& [c, w] : chosen) {
        const RpInfo& info = index.rp(c->rp);
        if (info.building_id != win->building || info.floor_id != win->floor) continue;
        result.rp_ids.push_back(info.id);
        wsum += w;
        x += w * info.at.x;
        y += w * info.at.y;
    }
    result.at = Point{x / wsum, y / wsum};

    const std::size_t n_candidates = std::min(n_listed, static_cast<std::size_t>(std::max(0, options.candidates)));
    for (std::size_t j = 0; j < n_candidates; ++j) {
        const Scored& c = scored[j];
        const RpInfo& info = index.rp(c.rp);
        result.candidates.push_back(Candidate{info.id, info.at, c.score, info.floor_id, info.building_id, c.shared});
    }
    return result;
}

}  // namespace locus::match
