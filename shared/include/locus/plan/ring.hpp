#pragma once
// Geometry of the plan's rings and polygons, shared by validation and the walk grid.
#include "locus/plan/plan.hpp"

namespace locus::plan {

// Shoelace area, positive for counter-clockwise rings; the closing point may be repeated.
double signed_area(const Ring& ring);

// Even-odd test; a point exactly on an edge may fall either way, which is harmless here
// because the grid samples cell centres and clearance keeps paths off the edges.
bool ring_contains(const Ring& ring, Point p);

// Inside the outer ring and in none of the holes.
bool polygon_contains(const Polygon& polygon, Point p);

// A point well inside the polygon: its centroid when that is inside (and in no hole), else
// the middle of the widest stretch inside along a horizontal line through it (an L, a U, a
// ring around a courtyard). What a space without a room is found and routed to.
Point interior_point(const Polygon& polygon);

struct Bounds {
    double xmin = 0.0, ymin = 0.0, xmax = 0.0, ymax = 0.0;
    bool contains(Point p) const { return p.x >= xmin && p.x <= xmax && p.y >= ymin && p.y <= ymax; }
};
Bounds bounds_of(const Ring& ring);

}  // namespace locus::plan
