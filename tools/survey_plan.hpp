#pragma once
// Proposes a reference-point grid for a floor (docs/spec.md §3.1): ceil(A / c²) points are needed for
// area A and cell side c. The grid has ceil(w/c) × ceil(h/c) cells of side ≤ c, one RP at each
// cell centre, so it never has fewer points than required; when the floor has rooms, centres
// outside every room are dropped (nobody can stand there to scan).
#include <cstddef>
#include <string>
#include <vector>

#include "locus/geometry.hpp"

namespace locus::tools::survey_plan {

struct PlannedRp {
    std::string name;  // "g<row>_<col>", rows from y = 0 upward, both zero-padded to 3 digits
    Point at;
};

struct Plan {
    std::size_t required = 0;  // ceil(width · height / cell²)
    std::size_t columns = 0, rows = 0;
    std::size_t outside_rooms = 0;  // grid points dropped
    std::vector<PlannedRp> points;
};

// Throws std::invalid_argument for a non-positive size or cell, or more than 1e6 cells.
Plan plan_grid(double width, double height, double cell, const std::vector<Room>& rooms = {});

}  // namespace locus::tools::survey_plan
