#include <cmath>

#include "../accumulate.hpp"
#include "../estimate.hpp"
#include "matchers.hpp"

namespace locus::match::detail {

// nn score: √Σ over the shared APs of the squared mean difference, plus γ per AP the RP
// stores beyond the number the query heard.
std::optional<Result> localize_nn(const Index& index, const Query& query, const Options& options, bool bsb_first, Scratch& s) {
    const QueryTotals q =
        prepare_query(index, query, static_cast<int>(options.representation), s, [](double) { return 0.0; });
    walk(index, options, s, [&](const Known& k, const PostingList& list, std::size_t j, std::uint32_t rp) {
        const double d = list.mean[j] - k.rss;
        s.acc[rp] += d * d;
    });
    std::vector<Scored>& scored = collect(s, [&](Scored& sc, std::uint32_t i, double acc) {
        const double extra = std::max(0.0, static_cast<double>(index.rp(i).ap_count) - q.n_aps);
        const double nn = std::sqrt(acc) + options.gamma * extra;
        sc.key1 = bsb_first ? -sc.shared : nn;
        sc.key2 = bsb_first ? nn : 0.0;
        sc.score = nn;
    });
    if (scored.empty()) return std::nullopt;
    const std::size_t n_listed = listed(scored, options.candidates, std::max(1, options.k));
    rank(scored, n_listed);
    if (!bsb_first)
        return estimate(index, Algorithm::nn, scored, tied_with_best(scored, options.tolerance), n_listed, options);
    // bsbnn: the tolerance applies to the nn score among the RPs with the top bsb count.
    const Scored& best = scored.front();
    const Chosen chosen = tied(scored, [&](const Scored& c) {
        return c.key1 == best.key1 && within_tolerance(c.key2, best.key2, options.tolerance);
    });
    return estimate(index, Algorithm::bsbnn, scored, chosen, n_listed, options);
}

}  // namespace locus::match::detail
