#pragma once
// One function per matcher; match::localize picks one by Algorithm and hands it the
// workspace's scratch, sized for the index and cleared. Each returns nullopt when no RP
// left after `near` shares an AP with the query.
#include <optional>

#include "locus/match/localize.hpp"

namespace locus::match::detail {

struct Scratch;

std::optional<Result> localize_bsb(const Index& index, const Query& query, const Options& options, Scratch& s);
// nn ranks by the nn score; bsbnn by the bsb count first, then the nn score among equals.
std::optional<Result> localize_nn(const Index& index, const Query& query, const Options& options, bool bsb_first, Scratch& s);
// wknn weighs each of the k nearest by 1/distance; knn averages them plainly.
std::optional<Result> localize_knn(const Index& index, const Query& query, const Options& options, bool weighted, Scratch& s);
std::optional<Result> localize_bayes(const Index& index, const Query& query, const Options& options, Scratch& s);

}  // namespace locus::match::detail
