#include "../accumulate.hpp"
#include "../estimate.hpp"
#include "matchers.hpp"

namespace locus::match::detail {

// Score: the number of APs the RP shares with the query, higher first.
std::optional<Result> localize_bsb(const Index& index, const Query& query, const Options& options, Scratch& s) {
    prepare_query(index, query, static_cast<int>(options.representation), s, [](double) { return 0.0; });
    walk(index, options, s, [](const Known&, const PostingList&, std::size_t, std::uint32_t) {});
    std::vector<Scored>& scored = collect(s, [](Scored& sc, std::uint32_t, double) {
        sc.key1 = -sc.shared;
        sc.score = sc.shared;
    });
    if (scored.empty()) return std::nullopt;
    const std::size_t n_listed = listed(scored, options.candidates, std::max(1, options.k));
    rank(scored, n_listed);
    return estimate(index, Algorithm::bsb, scored, tied_with_best(scored, options.tolerance), n_listed, options);
}

}  // namespace locus::match::detail
