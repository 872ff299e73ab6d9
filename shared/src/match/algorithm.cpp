#include "locus/match/algorithm.hpp"

#include <array>
#include <string>

namespace locus::match {

namespace {
template <typename E, std::size_t N>
std::optional<E> find_name(const std::array<std::string_view, N>& names, std::string_view name) {
    for (std::size_t i = 0; i < N; ++i)
        if (names[i] == name) return static_cast<E>(i);
    return std::nullopt;
}

constexpr std::array<std::string_view, 6> kAlgorithms{"bsb", "nn", "bsbnn", "knn", "wknn", "bayes"};
constexpr std::array<Algorithm, 6> kAllAlgorithms{Algorithm::bsb, Algorithm::nn, Algorithm::bsbnn,
                                                  Algorithm::knn, Algorithm::wknn, Algorithm::bayes};
constexpr std::array<std::string_view, 3> kRepresentations{"positive", "exponential", "powed"};
constexpr std::array<std::string_view, 3> kDistances{"euclidean", "manhattan", "sorensen"};
constexpr std::array<std::string_view, 2> kEstimates{"map", "mean"};
}  // namespace

std::optional<Algorithm> parse_algorithm(std::string_view name) { return find_name<Algorithm>(kAlgorithms, name); }
std::string_view to_string(Algorithm a) { return kAlgorithms[static_cast<std::size_t>(a)]; }
std::span<const Algorithm> all_algorithms() { return kAllAlgorithms; }

std::optional<Representation> parse_representation(std::string_view name) {
    return find_name<Representation>(kRepresentations, name);
}
std::string_view to_string(Representation r) { return kRepresentations[static_cast<std::size_t>(r)]; }

std::optional<Distance> parse_distance(std::string_view name) {
    // "sørensen" is how the literature spells it; accept it too.
    if (name == "s\xc3\xb8rensen") return Distance::sorensen;
    return find_name<Distance>(kDistances, name);
}
std::string_view to_string(Distance d) { return kDistances[static_cast<std::size_t>(d)]; }

std::optional<BayesEstimate> parse_bayes_estimate(std::string_view name) {
    return find_name<BayesEstimate>(kEstimates, name);
}
std::string_view to_string(BayesEstimate e) { return kEstimates[static_cast<std::size_t>(e)]; }

}  // namespace locus::match
