#pragma once
// Turn-by-turn steps from a route's legs, structured (for an app to draw arrows) and as plain
// English (for one to read out). Rules, in docs/routing.md: a heading change under 20° is no
// turn, 20–45° is slight, 45–135° a turn, above 135° sharp; bends closer together than
// kMergeTurnsWithin add up to one turn, so the zigzag of a door passage is not announced.
#include <string>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/plan/plan.hpp"

namespace locus::plan {

inline constexpr double kMergeTurnsWithin = 1.0;  // metres

enum class StepKind { walk, slight_left, turn_left, sharp_left, slight_right, turn_right, sharp_right, take_connector, arrive };

struct Step {
    StepKind kind = StepKind::walk;
    double distance_m = 0.0;  // walk only
    ConnectorKind connector = ConnectorKind::stairs;  // take_connector only
    std::string connector_name;                       // take_connector only
    int from_level = 0, to_level = 0;                 // take_connector only
    std::string text;  // "Walk 12 m", "Turn left", "Take the stairs up to level 2"
};

// One floor's part of a route: the polyline walked there.
struct Leg {
    std::int64_t floor_id = 0;
    int level = 0;
    std::vector<Point> path;
    double length_m = 0.0;
};

// A ride between two legs.
struct Transfer {
    ConnectorKind kind = ConnectorKind::stairs;
    std::string name;
    int from_level = 0, to_level = 0;
    double seconds = 0.0;
};

// legs.size() == transfers.size() + 1: transfer i leads from leg i to leg i + 1.
std::vector<Step> instructions(const std::vector<Leg>& legs, const std::vector<Transfer>& transfers);

}  // namespace locus::plan
