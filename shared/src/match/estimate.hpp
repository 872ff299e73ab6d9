#pragma once
// The answer every matcher gives from its chosen RPs: building and floor by their vote, the
// weighted centroid of the winning floor's RPs, and the ranked candidate list.
#include <vector>

#include "candidates.hpp"
#include "locus/match/localize.hpp"

namespace locus::match::detail {

// `ranked`: every candidate, the first `n_listed` sorted; `chosen`: the answer's RPs, best
// first, pointing into `ranked` or a pool taken from it.
Result estimate(const Index& index, Algorithm algorithm, const std::vector<Scored>& ranked, const Chosen& chosen,
                std::size_t n_listed, const Options& options);

}  // namespace locus::match::detail
