#pragma once
// The online matchers of docs/spec.md §4 over an Index: bsb, nn, bsbnn (Traini 2017), knn, wknn and
// a HORUS-style Gaussian bayes (Youssef, Agrawala 2005). Pure and deterministic: equal scores are broken by
// RP position in the index, tied winners are all reported and their centroid answered.
#include <optional>
#include <string>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/match/algorithm.hpp"
#include "locus/match/index.hpp"
#include "locus/match/options.hpp"
#include "locus/match/query.hpp"
#include "locus/match/workspace.hpp"

namespace locus::match {

struct Candidate {
    long long rp_id = 0;
    Point at;
    double score = 0.0;  // in the algorithm's own unit (see docs/matchers.md)
    long long floor_id = 0;
    long long building_id = 0;
    int matched_aps = 0;  // online APs this RP also stores
};

struct Result {
    Point at;
    long long floor_id = 0;
    long long building_id = 0;
    std::vector<long long> rp_ids;  // the RPs the answer is built from (tied set, k nearest…)
    double score = 0.0;             // the best candidate's score
    int matched_aps = 0;            // the best candidate's shared APs
    std::string algorithm;
    std::vector<Candidate> candidates;  // best first, at most Options::candidates
};

// nullopt when no candidate RP (after the `near` filter) shares an AP with the query.
// `workspace` is this call's working memory (see workspace.hpp): one per thread, reused.
std::optional<Result> localize(const Index& index, const Query& query, Algorithm algorithm, const Options& options,
                               Workspace& workspace);

}  // namespace locus::match
