#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>

#include "../accumulate.hpp"
#include "../estimate.hpp"
#include "../floor_vote.hpp"
#include "../knn_distance.hpp"
#include "matchers.hpp"

namespace locus::match::detail {

namespace {

constexpr double kLog2Pi = 1.8378770664093453;  // log(2π)

// Each voter's share of a floor vote: the posterior mass, the loudest APs, the knn neighbours.
struct Shares {
    double mass, aps, knn;
};

Shares shares_of(const Options& options, bool with_knn) {
    const double knn = with_knn ? std::clamp(options.floor_knn_weight, 0.0, 1.0) : 0.0;
    const double aps = options.floor_aps > 0 ? std::clamp(options.floor_ap_weight, 0.0, 1.0 - knn) : 0.0;
    return {1.0 - knn - aps, aps, knn};
}

// Casts the floor vote once per entry of `shares` into the matching `votes`: posterior mass
// over every candidate RP, plus, as the shares say, the loudest APs' home floors and the knn
// vote of the nearest RPs. The voters are worked out once for all. Reorders s.known.
void cast_floor_votes(const Index& index, const Options& options, Scratch& s, const std::vector<Scored>& scored,
                      double temperature, std::span<const Shares> shares, std::span<FloorVote> votes,
                      std::vector<Scored>& scratch) {
    const Scored& best = scored.front();
    const double floor_t = options.floor_temperature > 0.0 ? options.floor_temperature : temperature;
    std::vector<double>& mass_of = s.weights;  // each candidate's unnormalised posterior
    mass_of.clear();
    double mass = 0.0;
    for (const auto& c : scored) mass += mass_of.emplace_back(std::exp((best.key1 - c.key1) / floor_t));
    for (std::size_t v = 0; v < shares.size(); ++v)
        for (std::size_t j = 0; j < scored.size(); ++j)
            votes[v].add(index.rp(scored[j].rp), shares[v].mass * mass_of[j] / mass);
    if (std::any_of(shares.begin(), shares.end(), [](const Shares& sh) { return sh.aps > 0.0; })) {
        // The strongest APs first; an AP whose home RP lies outside `near` does not vote,
        // so the winning floor always has candidates.
        std::vector<Known>& loudest = s.known;
        const std::size_t n = std::min(loudest.size(), static_cast<std::size_t>(options.floor_aps));
        std::partial_sort(loudest.begin(), loudest.begin() + static_cast<long>(n), loudest.end(),
                          [](const Known& a, const Known& b) { return a.rss != b.rss ? a.rss > b.rss : a.ap < b.ap; });
        for (std::size_t j = 0; j < n; ++j) {
            const std::uint32_t home = index.strongest_rp(loudest[j].ap);
            if (outside(index, home, options)) continue;
            for (std::size_t v = 0; v < shares.size(); ++v)
                if (shares[v].aps > 0.0) votes[v].add(index.rp(home), shares[v].aps / static_cast<double>(n));
        }
    }
    if (options.floor_knn > 0) {  // then the last vote is the one that hears the knn neighbours
        std::vector<Scored>& near_rps = scratch;
        near_rps.assign(scored.begin(), scored.end());
        const std::size_t n = std::min(near_rps.size(), static_cast<std::size_t>(options.floor_knn));
        auto closer = [](const Scored& a, const Scored& b) { return a.aux != b.aux ? a.aux < b.aux : a.rp < b.rp; };
        std::partial_sort(near_rps.begin(), near_rps.begin() + static_cast<long>(n), near_rps.end(), closer);
        for (std::size_t j = 0; j < n; ++j)
            votes.back().add(index.rp(near_rps[j].rp), shares.back().knn / static_cast<double>(n));
        scratch.clear();
    }
}

// Picks the position's floor by the vote (without the knn neighbours when they name the floor
// only) and returns that floor's candidates ranked as far as n_listed, or `scored` itself
// when every candidate is on one floor. `label`: the floor the answer names, when that comes
// from a second vote with the knn neighbours. Reorders s.known.
const std::vector<Scored>& floor_pool(const Index& index, const Options& options, Scratch& s,
                                      const std::vector<Scored>& scored, std::size_t n_listed, double temperature,
                                      bool floor_knn, std::vector<Scored>& on_floor,
                                      std::optional<FloorVote::Group>& label) {
    const bool split = floor_knn && !options.floor_knn_position;
    const Shares shares[2] = {shares_of(options, floor_knn && !split), shares_of(options, true)};
    FloorVote votes[2];
    const std::size_t n_votes = split ? 2 : 1;
    cast_floor_votes(index, options, s, scored, temperature, std::span(shares, n_votes), std::span(votes, n_votes),
                     on_floor);
    // One group means every candidate is on that floor (a radio map's index, or a map heard
    // on one floor only), and `scored` is already that floor's list, ranked.
    if (split && votes[1].size() > 1) label = votes[1].winner();
    if (votes[0].size() <= 1) return scored;
    const FloorVote::Group& g = votes[0].winner();
    for (const auto& c : scored) {
        const RpInfo& info = index.rp(c.rp);
        if (info.building_id == g.building && info.floor_id == g.floor) on_floor.push_back(c);
    }
    rank(on_floor, std::min(on_floor.size(), n_listed));
    return on_floor;
}

}  // namespace

std::optional<Result> localize_bayes(const Index& index, const Query& query, const Options& options, Scratch& s) {
    const int rep = static_cast<int>(options.representation);
    const IndexParams& params = index.params();
    // A zero floor would divide by the zero variance of an AP sampled once.
    const double sigma_floor = std::max(options.sigma_floor, 0.1);
    const double sigma2_floor = sigma_floor * sigma_floor;
    const double log_sigma2_floor = std::log(sigma2_floor);
    // No AP's squared standardised residual counts beyond κ², so one glitched reading
    // (phones report 0 dBm for APs heard at -80 elsewhere) cannot outweigh the rest.
    const double kappa2 = options.outlier_sigmas > 0.0 ? options.outlier_sigmas * options.outlier_sigmas
                                                       : std::numeric_limits<double>::infinity();
    const double penalty_base = std::log(params.min_detection) - 0.5 * (kLog2Pi + log_sigma2_floor);

    // An AP the RP does not store counts as if it were stored with the missing value, the
    // floored variance and the minimum detection rate.
    const QueryTotals q = prepare_query(index, query, rep, s, [&](double rss) {
        const double d = rss - params.missing_rss;
        return penalty_base - 0.5 * std::min(d * d / sigma2_floor, kappa2);
    });
    const bool floor_knn = options.floor_knn > 0;
    const KnnDistance knn(index, options, q);
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
        walk(index, options, s, [&](const Known& k, const PostingList& list, std::size_t j, std::uint32_t rp) {
            gauss(k, list, j, rp);
            s.acc_knn[rp] += knn.term(list.rep[rep][j], k.rep);
        });
    } else {
        walk(index, options, s, gauss);
    }
    std::vector<Scored>& scored = collect(s, [&](Scored& sc, std::uint32_t i, double acc) {
        double ll = q.penalty_sum + index.log_miss_sum(i) + acc;
        // Phones disagree on RSS by a near-constant offset δ: the best δ for this RP under a
        // N(0, offset_sigma²) prior, in closed form, and the Gaussian terms' gain from using it.
        if (options.offset_sigma > 0.0) {
            const double wd = s.acc_wd[i];
            ll += 0.5 * wd * wd / (s.acc_w[i] + 1.0 / (options.offset_sigma * options.offset_sigma));
        }
        sc.key1 = -ll;
        sc.score = ll;
        if (floor_knn) sc.aux = knn(i, s.acc_knn[i]);
    });
    if (scored.empty()) return std::nullopt;

    const int k = std::max(1, options.bayes_k > 0 ? options.bayes_k : options.k);
    const std::size_t n_listed = listed(scored, options.candidates, k);
    rank(scored, n_listed);
    const double temperature = std::max(options.temperature, 1e-9);
    std::vector<Scored>& on_floor = s.on_floor;
    on_floor.clear();
    std::optional<FloorVote::Group> label;
    const std::vector<Scored>& pool =
        floor_pool(index, options, s, scored, n_listed, temperature, floor_knn, on_floor, label);

    const Scored& best = scored.front();
    const Chosen chosen = options.estimate == BayesEstimate::mean
                              ? top_k(pool, k, [&](const Scored& c) { return std::exp((best.key1 - c.key1) / temperature); })
                              : tied_with_best(pool, options.tolerance);
    Result r = estimate(index, Algorithm::bayes, scored, chosen, n_listed, options);
    if (label) {
        r.building_id = label->building;
        r.floor_id = label->floor;
    }
    return r;
}

}  // namespace locus::match::detail
