#include "locus/match/localize.hpp"

#include "accumulate.hpp"
#include "matchers/matchers.hpp"

namespace locus::match {

// The one place that knows every matcher.
std::optional<Result> localize(const Index& index, const Query& query, Algorithm algorithm, const Options& options,
                               Workspace& workspace) {
    detail::Scratch& s = detail::scratch_for(index, workspace);
    switch (algorithm) {
        case Algorithm::bsb: return detail::localize_bsb(index, query, options, s);
        case Algorithm::nn: return detail::localize_nn(index, query, options, false, s);
        case Algorithm::bsbnn: return detail::localize_nn(index, query, options, true, s);
        case Algorithm::knn: return detail::localize_knn(index, query, options, false, s);
        case Algorithm::wknn: return detail::localize_knn(index, query, options, true, s);
        case Algorithm::bayes: return detail::localize_bayes(index, query, options, s);
    }
    return std::nullopt;
}

}  // namespace locus::match
