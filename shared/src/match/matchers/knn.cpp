#include "../accumulate.hpp"
#include "../estimate.hpp"
#include "../knn_distance.hpp"
#include "matchers.hpp"

namespace locus::match::detail {

std::optional<Result> localize_knn(const Index& index, const Query& query, const Options& options, bool weighted, Scratch& s) {
    const int rep = static_cast<int>(options.representation);
    const QueryTotals q = prepare_query(index, query, rep, s, [](double) { return 0.0; });
    const KnnDistance knn(index, options, q);
    walk(index, options, s, [&](const Known& k, const PostingList& list, std::size_t j, std::uint32_t rp) {
        s.acc[rp] += knn.term(list.rep[rep][j], k.rep);
    });
    std::vector<Scored>& scored = collect(s, [&](Scored& sc, std::uint32_t i, double acc) {
        const double d = knn(i, acc);
        sc.key1 = d;
        sc.score = d;
    });
    if (scored.empty()) return std::nullopt;
    const int k = std::max(1, options.k);
    const std::size_t n_listed = listed(scored, options.candidates, k);
    rank(scored, n_listed);
    const Chosen chosen =
        top_k(scored, k, [&](const Scored& c) { return weighted ? 1.0 / std::max(c.key1, 1e-9) : 1.0; });
    return estimate(index, weighted ? Algorithm::wknn : Algorithm::knn, scored, chosen, n_listed, options);
}

}  // namespace locus::match::detail
