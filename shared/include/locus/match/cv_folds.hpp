#pragma once
// Which cross-validation fold each surveyed scan goes to (`locus eval … --cv K --cv-blocks`).
// Every scheme deals whole blocks of surveyed positions to the folds, so a held-out position
// never finds itself in the map; the schemes differ in what else leaves with it:
// - position: each position is its own block (its survey neighbours stay in the map);
// - spatial G: positions in one G × G metre cell of one floor form a block, so a held-out
//   position's nearest surveyed neighbours (within the cell) leave with it;
// - order N: N consecutive positions in survey (file) order form a block, a stretch of one
//   survey walk or session.
// Pure and deterministic: blocks are taken in order of their first scan and each goes to the
// fold holding the fewest positions so far (the lowest such fold on a tie); with one-position
// blocks that is round-robin in first-appearance order.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "locus/geometry.hpp"

namespace locus::match {

// Where one scan was taken: scans with equal building, floor and point are one position.
struct FoldSite {
    long long building = 0, floor = 0;
    Point at;
};

enum class FoldBlocks { position, spatial, order };

// The smallest spatial cell side: a centimetre is below any survey's position accuracy, and a
// bound keeps coordinate / side far inside the range of a cell index.
inline constexpr double kMinCellM = 0.01;

struct FoldScheme {
    FoldBlocks blocks = FoldBlocks::position;
    double cell_m = 0.0;  // spatial: the cell's side (>= kMinCellM)
    std::size_t run = 1;  // order: positions per block (>= 1)
};

// "position", "spatial:G" (G metres, >= kMinCellM) or "order:N" (N positions, >= 1); nullopt
// otherwise. to_string gives back text that parses to the same scheme.
std::optional<FoldScheme> parse_fold_scheme(std::string_view text);
std::string to_string(const FoldScheme& scheme);

// The fold (0 … k−1) of each site. k must be at least 1; with fewer blocks than k some folds
// stay empty. Throws std::invalid_argument on k < 1 or a scheme outside the ranges above.
std::vector<int> assign_folds(std::span<const FoldSite> sites, int k, const FoldScheme& scheme);

}  // namespace locus::match
