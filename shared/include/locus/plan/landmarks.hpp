#pragma once
// Grid distances from a few fixed cells of a floor (its connectors and the free cells nearest
// its corners), computed once per floor. By the triangle inequality they give A* lower
// bounds that see walls and doors ("ALT"), where straight-line bounds send the search into
// every room near the line; and from a connector they are exact walking distances.
#include <limits>
#include <vector>

#include "locus/plan/walk_grid.hpp"

namespace locus::plan {

inline constexpr float kNoPath = std::numeric_limits<float>::infinity();

// Distances from each source to every cell, cell-major so the heuristic's reads for one cell
// share a cache line: metres[cell * sources.size() + l] is from sources[l] to cell.
struct Landmarks {
    std::vector<int> sources;
    std::vector<float> metres;  // kNoPath: not connected
    const float* at(int cell) const { return metres.data() + static_cast<std::size_t>(cell) * sources.size(); }
};

// Dijkstra over the grid's moves from each source (a source of −1 reaches nothing). Avoided
// spaces are ignored: the distances stay lower bounds under every constraint.
Landmarks landmarks_from(const WalkGrid& grid, const std::vector<int>& sources);

// The free cells nearest the four corners of the grid, for landmarks that spread out.
std::vector<int> corner_cells(const WalkGrid& grid);

}  // namespace locus::plan
