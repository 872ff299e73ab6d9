#pragma once
// Self-tuning of a radio map (POST /v1/radiomaps/{id}/tune, `locus eval fingerprints --tune`):
// K-fold cross-validation over the radio map's own RPs. Each fold's RPs are taken out of the
// index and localized, each with its stored per-AP means as the scan, by every candidate
// setting of a small fixed grid; the setting with the lowest mean error wins. Pure and
// deterministic: the folds come from a fixed-seed shuffle of the RPs' positions (or whole
// blocks of them, TuneLimits::blocks, which the server never sets).
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "locus/match/algorithm.hpp"
#include "locus/match/cv_folds.hpp"
#include "locus/match/index.hpp"
#include "locus/match/options.hpp"

namespace locus::match {

// A matcher with its options: what a request that names neither gets.
struct Setting {
    Algorithm algorithm = kDefaultAlgorithm;
    Options options;
};

struct TuneCandidate {
    std::string name;  // e.g. "wknn k=5 powed sorensen"
    Setting setting;
};

// The candidates, the built-in default first (so a tie keeps it): bayes, and knn/wknn with a
// few k and representations. Small on purpose: the cost is candidates × queries.
std::vector<TuneCandidate> tune_grid();

struct TuneLimits {
    int folds = 10;                  // K; fewer when the map has fewer RPs (then leave-one-out)
    std::size_t max_queries = 2000;  // held-out RPs localized at most (a fixed-seed subsample)
    // What a fold takes out whole (match::assign_folds over the RPs in the map's order, so the
    // blocks of a spatial or order scheme see the map as surveyed). Unset: each RP on its own,
    // dealt from the fixed-seed shuffle. A scheme that leaves fewer than 2 folds holding RPs
    // falls back to that shuffle.
    std::optional<FoldScheme> blocks{};
};

// EvAAL's penalties (IPIN 2015 UJIIndoorLoc track): 4 m per floor of difference, 50 m for a
// wrong building, on top of the horizontal error. A held-out RP that shares no AP with the
// rest of the map counts the building penalty.
inline constexpr double kFloorPenaltyM = 4.0;
inline constexpr double kBuildingPenaltyM = 50.0;

struct TuneRow {
    std::string name;
    Setting setting;
    double mean_error_m = 0.0;       // EvAAL-style: what the choice minimises
    double mean_horizontal_m = 0.0;  // over answered queries
    double floor_hit_rate = 0.0;     // right building and floor, over all queries
    double building_hit_rate = 0.0;
    std::size_t unanswered = 0;
};

struct TuneReport {
    std::vector<TuneRow> rows;  // in grid order
    std::size_t best = 0;       // row with the lowest mean_error_m (the first on a tie)
    std::size_t rps = 0, folds = 0, queries = 0;
    bool subsampled = false;  // fewer queries than RPs (TuneLimits::max_queries)
};

// The level of a floor id, for the floor penalty (|level difference| floors).
using FloorLevel = std::function<long long(long long floor_id)>;

struct TuneRefused : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// Throws TuneRefused when there are fewer than 2 RPs, or an empty grid.
TuneReport tune(const std::vector<IndexedRp>& rps, std::span<const TuneCandidate> grid, const FloorLevel& level_of,
                const TuneLimits& limits = {}, const IndexParams& params = {});

}  // namespace locus::match
