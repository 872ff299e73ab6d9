#pragma once
// Names of the matchers and of their knobs, as the API and the CLI spell them.
#include <optional>
#include <span>
#include <string_view>

namespace locus::match {

enum class Algorithm { bsb, nn, bsbnn, knn, wknn, bayes };

// The matcher used when a request names none: the most accurate on UJIIndoorLoc, on the
// tuning users (2, 4, …, 18) and on the report users (1, 3, …, 17) alike (docs/matchers.md).
// The server's requests and `locus eval --algorithm default` both read it here.
inline constexpr Algorithm kDefaultAlgorithm = Algorithm::bayes;

std::optional<Algorithm> parse_algorithm(std::string_view name);
std::string_view to_string(Algorithm a);
// Every algorithm, in the order reports list them.
std::span<const Algorithm> all_algorithms();

// RSS representation used by knn/wknn (Torres-Sospedra et al. 2015). Every form maps the
// index's missing value (an AP not heard) to 0, so "not heard" costs the same everywhere.
enum class Representation { positive, exponential, powed };
std::optional<Representation> parse_representation(std::string_view name);
std::string_view to_string(Representation r);

enum class Distance { euclidean, manhattan, sorensen };
std::optional<Distance> parse_distance(std::string_view name);
std::string_view to_string(Distance d);

// What bayes answers: the single most likely RP, or the posterior-weighted mean of the top k.
enum class BayesEstimate { map, mean };
std::optional<BayesEstimate> parse_bayes_estimate(std::string_view name);
std::string_view to_string(BayesEstimate e);

}  // namespace locus::match
