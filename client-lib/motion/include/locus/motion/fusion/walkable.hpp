#pragma once
// Where a pedestrian can walk on a floor, in one of two forms:
//  - rooms and doors (the simulator's scenarios, walk files): inside the rooms, and from one
//    room to another only through a door. The core's FloorPlan has rooms but no walls, so
//    doors are given here as segments lying on the shared wall (a corridor split into several
//    rooms gets a "door" as wide as the open boundary);
//  - a floor plan as the server holds it (plan::Plan: spaces, walls, door gaps), from
//    Walkable::from_plan; then the plan alone decides (plan_walkable.hpp).
#include <memory>
#include <vector>

#include "locus/motion/fusion/plan_walkable.hpp"
#include "locus/geometry.hpp"

namespace locus::fusion {

struct Walkable {
    FloorPlan plan;
    std::vector<Segment> doors;
    // With no door data (e.g. rooms read from the server) rooms that touch are open to each other
    // everywhere: set this to false and only "stay inside some room" is enforced.
    bool walls_between_rooms = true;
    // Set by from_plan: the floor plan replaces rooms and doors. Shared, because filters copy
    // their Walkable and a plan's grid is large.
    std::shared_ptr<const PlanWalkable> floor_plan;

    // Throws as PlanWalkable's constructor does.
    static Walkable from_plan(locus::plan::Plan plan);

    bool inside(Point p) const;  // in some room, or walkable on the floor plan
    // A move is legal when it ends inside a room and either stays in one room or passes
    // through a door. A point outside every room may only move back into a room. On a
    // floor plan: PlanWalkable::can_move.
    bool can_move(Point from, Point to) const;
};

}  // namespace locus::fusion
