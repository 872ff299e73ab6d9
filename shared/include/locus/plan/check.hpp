#pragma once
// Validation of plans before they are routed on: the grid and the router assume what these
// checks establish (finite, closed, simple rings; doors on walls; connectors that pair up),
// so a plan that fails them gives routes that are wrong in ways nobody would notice.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "locus/plan/plan.hpp"

namespace locus::plan {

struct PlanProblem {
    std::string feature;  // "spaces[3] 'Lab'", "walls[2]", "doors[0] 'D1'", "connectors[1] 's1'"
    std::string problem;  // what is wrong, in words
};

// The largest floor a plan may cover (its bounding box, m²): 500 m × 500 m, a large mall. The
// router's grid and landmarks grow with this area (docs/routing.md: 4 M cells at 0.25 m, and
// their landmark distances), so a plan drawn in millimetres instead of metres is refused here
// rather than exhausting the server's memory on the first route.
inline constexpr double kMaxPlanArea = 250000.0;

// A door farther than this from every wall opens nothing: it is a drawing mistake.
inline constexpr double kDoorWallTolerance = 0.5;

// One plan on its own: every coordinate finite and within ±kMaxPlanCoordinate; rings closed
// (first == last), ≥ 4 points, non-zero area and not self-intersecting; holes inside their
// outer ring; walls with ≥ 2 distinct points; doors within kDoorWallTolerance of a wall;
// connector ids non-empty and unique, links naming a connector; the bounding box of all of it
// within kMaxPlanArea. The self-intersection test
// compares every pair of edges of a ring, O(n²): fine up to a few thousand points per ring.
std::vector<PlanProblem> check_plan(const Plan& plan);

// The links between floors of a whole building at once, which no single plan can check:
// every link names a known floor other than its own and a connector on it, and that
// connector links back (the rules and words of link_problems in plan.hpp, which checks one
// floor's plan as it arrives). Features are prefixed with the floor: "floor 2 connectors[0]
// 's1'". A floor id given twice is a problem.
std::vector<PlanProblem> check_links(const std::vector<std::pair<std::int64_t, const Plan*>>& floors);

}  // namespace locus::plan
