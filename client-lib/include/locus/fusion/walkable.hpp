#pragma once
// Where a pedestrian can walk on a floor: inside the rooms, and from one room to another only
// through a door. The floor plan of the core has rooms but no walls, so doors are given
// here as segments lying on the shared wall (a corridor split into several rooms gets a
// "door" as wide as the open boundary).
#include <vector>

#include "locus/geometry.hpp"

namespace locus::fusion {

struct Walkable {
    FloorPlan plan;
    std::vector<Segment> doors;
    // With no door data (e.g. a plan from the server) rooms that touch are open to each other
    // everywhere: set this to false and only "stay inside some room" is enforced.
    bool walls_between_rooms = true;

    bool inside(Point p) const;  // in some room
    // A move is legal when it ends inside a room and either stays in one room or passes
    // through a door. A point outside every room may only move back into a room.
    bool can_move(Point from, Point to) const;
};

}  // namespace locus::fusion
