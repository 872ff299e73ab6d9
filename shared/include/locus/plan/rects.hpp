#pragma once
// A space's outline as the union of axis-aligned rectangles an API room is made of (rooms
// answer "which room am I in" with rectangles, geometry.hpp), so a room kept in step with a
// plan's space covers the same floor.
#include <cstddef>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/plan/plan.hpp"

namespace locus::plan {

// More slabs than this are merged into this many (see rects_of): a room is a handful of
// rectangles, not one per vertex of a curved wall.
inline constexpr std::size_t kMaxRoomSlabs = 64;
// More covered intervals in one slab than this (a comb-shaped space) are merged across their
// narrowest gaps, so that a room has at most kMaxRoomSlabs × kMaxSlabIntervals = 960
// rectangles: within the API's 1000 per room, and cheap to write.
inline constexpr std::size_t kMaxSlabIntervals = 15;

// Vertical slab decomposition: the polygon (outer ring minus holes, even-odd) is cut at
// each distinct x of its vertices; within a slab the covered y-intervals are read at the
// slab's middle x and each becomes a rectangle; a rectangle continues the one of the previous
// slab with the same y-interval. Exact for rectilinear polygons, holes included. A slanted
// edge is replaced by its height at the slab's middle, so a triangle or a diagonal wall is
// approximated (the area is exact per slab for straight edges: the trapezoid's mean height).
// With more than kMaxRoomSlabs slabs, the cuts are thinned to kMaxRoomSlabs evenly chosen
// vertex x's, making even rectilinear polygons approximate; likewise a slab's intervals past
// kMaxSlabIntervals are joined across their narrowest gaps (the room then covers those gaps). Rectangles come ordered by xmin,
// then ymin; an empty or degenerate polygon gives none.
std::vector<Rect> rects_of(const Polygon& shape);

}  // namespace locus::plan
