#pragma once
// The rooms-and-doors form of a floor (Walkable's rooms, walk files, the simulator's
// scenarios) as a floor plan (plan::Plan): what the server would hold for that floor, so a
// scenario can be put on a server and map-matched on the plan form. Spaces are the rooms'
// rectangles (an L-shaped room gives two spaces of the same name and room id); walls are each
// room's outline, drawn once per room, so a wall between two rooms is drawn twice, as a plan
// drawn room by room would be (the walk grid's door gaps cut both); doors are the door
// segments. Rooms open to each other (walls_between_rooms false) give no walls and no
// doors: the outline of the spaces is the only barrier. The result passes plan::check_plan.
#include "locus/motion/fusion/walkable.hpp"
#include "locus/plan/plan.hpp"

namespace locus::fusion {

// A Walkable that already holds a floor plan gives that plan back.
locus::plan::Plan rooms_plan(const Walkable& rooms);

}  // namespace locus::fusion
