#pragma once
// Straightening a grid path by line of sight: from each kept vertex, jump to the farthest
// later vertex that can be walked to in a straight line.
#include <cstdint>
#include <vector>

#include "locus/plan/walk_grid.hpp"

namespace locus::plan {

// Whether walking straight from a to b stays on walkable cells not flagged in `blocked` (when
// given; both sampled every half cell), keeps the grid's clearance from every wall and
// crosses no jamb (both exact).
bool clear_line(const WalkGrid& grid, const std::vector<std::uint8_t>* blocked, Point a, Point b);

// The first and last points are kept; neighbouring points are trusted to be joinable (they
// are grid steps, or an endpoint and its snapped cell).
std::vector<Point> pull_string(const WalkGrid& grid, const std::vector<std::uint8_t>* blocked, const std::vector<Point>& path);

}  // namespace locus::plan
