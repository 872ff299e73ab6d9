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

struct Landmark {
    int cell = -1;
    std::vector<float> metres;  // grid distance from `cell` to each cell; kNoPath: not connected
};

// Dijkstra over the grid's moves from `source` (ignoring any avoided space: the distances stay
// lower bounds under every constraint).
Landmark landmark_at(const WalkGrid& grid, int source);

// The free cells nearest the four corners of the grid, for landmarks that spread out.
std::vector<int> corner_cells(const WalkGrid& grid);

}  // namespace locus::plan
