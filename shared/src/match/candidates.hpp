#pragma once
// Candidate RPs as the matchers rank them, and the two ways a matcher picks the set its
// answer is built from: the k best, or every RP tied with (or close to) the best.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace locus::match::detail {

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

inline bool within_tolerance(double value, double best, double tolerance) {
    return std::abs(value - best) <= tolerance * std::abs(best);
}

// How many candidates are ranked: enough for the listing and for the k an answer may use.
inline std::size_t listed(const std::vector<Scored>& scored, int candidates, int k) {
    return std::min(scored.size(), static_cast<std::size_t>(std::max({candidates, k, 1})));
}

// Sorts the first n best into place; the rest stay unordered.
inline void rank(std::vector<Scored>& scored, std::size_t n) {
    std::partial_sort(scored.begin(), scored.begin() + static_cast<long>(n), scored.end(), better);
}

struct Weighted {
    const Scored* scored;
    double weight;
};
using Chosen = std::vector<Weighted>;

// The first k of a ranked pool, `weight(c)` each.
template <typename Weight>
Chosen top_k(const std::vector<Scored>& ranked, int k, Weight&& weight) {
    Chosen chosen;
    const std::size_t n = std::min(ranked.size(), static_cast<std::size_t>(k));
    for (std::size_t j = 0; j < n; ++j) chosen.push_back(Weighted{&ranked[j], weight(ranked[j])});
    return chosen;
}

// Every RP of the pool for which `in(c)` holds, best first, weight 1. The pool need only be
// ranked as far as its listed prefix.
template <typename In>
Chosen tied(const std::vector<Scored>& pool, In&& in) {
    std::vector<const Scored*> set;
    for (const auto& c : pool)
        if (in(c)) set.push_back(&c);
    std::sort(set.begin(), set.end(), [](const Scored* a, const Scored* b) { return better(*a, *b); });
    Chosen chosen;
    for (const Scored* c : set) chosen.push_back(Weighted{c, 1.0});
    return chosen;
}

// Every RP whose key1 is within the tolerance of the best's.
inline Chosen tied_with_best(const std::vector<Scored>& ranked, double tolerance) {
    const double best = ranked.front().key1;
    return tied(ranked, [&](const Scored& c) { return within_tolerance(c.key1, best, tolerance); });
}

}  // namespace locus::match::detail
