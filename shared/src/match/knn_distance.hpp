#pragma once
// The knn distance over the union of APs, from a sum over the shared APs alone and the
// index's per-RP totals. Used by knn/wknn and by bayes's optional knn floor vote.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "accumulate.hpp"
#include "locus/match/index.hpp"
#include "locus/match/options.hpp"

namespace locus::match::detail {

class KnnDistance {
public:
    KnnDistance(const Index& index, const Options& options, const QueryTotals& q)
        : index_(index), rep_(static_cast<int>(options.representation)), distance_(options.distance),
          euclid_(options.distance == Distance::euclidean), q_sum_(q.rep_sum), q_sq_sum_(q.rep_sq_sum) {}

    // One shared AP's term, a and b its RP and query reps: the correction from "each side
    // heard alone" to "both heard" for this AP.
    double term(double a, double b) const { return euclid_ ? a * b : std::abs(a - b) - a - b; }

    double operator()(std::uint32_t i, double acc) const {
        if (euclid_) return std::sqrt(std::max(0.0, index_.rep_sq_sum(i, rep_) + q_sq_sum_ - 2.0 * acc));
        const double manhattan = std::max(0.0, index_.rep_sum(i, rep_) + q_sum_ + acc);
        if (distance_ == Distance::manhattan) return manhattan;
        const double total = index_.rep_sum(i, rep_) + q_sum_;
        return total > 0.0 ? manhattan / total : 1.0;
    }

private:
    const Index& index_;
    int rep_;
    Distance distance_;
    bool euclid_;
    double q_sum_, q_sq_sum_;
};

}  // namespace locus::match::detail
