#include "locus/match/localize.hpp"

#include "matchers/matchers.hpp"

namespace locus::match {

// The one place that knows every matcher.
std::optional<Result> localize(const Index& index, const Query& query, Algorithm algorithm, const Options& options) {
    switch (algorithm) {
        case Algorithm::bsb: return detail::localize_bsb(index, query, options);
        case Algorithm::nn: return detail::localize_nn(index, query, options, false);
        case Algorithm::bsbnn: return detail::localize_nn(index, query, options, true);
        case Algorithm::knn: return detail::localize_knn(index, query, options, false);
        case Algorithm::wknn: return detail::localize_knn(index, query, options, true);
        case Algorithm::bayes: return detail::localize_bayes(index, query, options);
    }
    return std::nullopt;
}

}  // namespace locus::match
