#pragma once
// Where a person can walk on one floor, as a grid of square cells (8-connected) built from a
// Plan. A grid rather than a visibility graph or navmesh: plans mix free-drawn walls, door
// gaps and overlapping spaces, and a grid handles all of them with one rule per cell and
// edge; the jagged grid paths are straightened afterwards (route.hpp). docs/routing.md has
// the measurements.
//
// Barriers are the walls minus their door gaps plus the edge of the walkable area (the
// outline of the union of the spaces). A cell is free when its centre is walkable and at
// least clearance_threshold() from every barrier, which keeps every grid edge between free
// cells at least `clearance` from them. At doors the clearance is measured from the wall as
// if the gap were wider (door_clear_radius()), so a narrow door stays passable; the wall
// pieces that widening hides (the jambs) still may not be crossed.
#include <cstdint>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/plan/plan.hpp"

namespace locus::plan {

struct GridOptions {
    double cell = 0.25;      // metres; a 0.9 m door is 3.6 cells
    double clearance = 0.3;  // metres kept from barriers, doors aside
};

// Directions of the 8 neighbours, counter-clockwise from east; bit d of WalkGrid::moves.
inline constexpr int kDirCol[8] = {1, 1, 0, -1, -1, -1, 0, 1};
inline constexpr int kDirRow[8] = {0, 1, 1, 1, 0, -1, -1, -1};

// How far (metres) an endpoint or connector may be from the nearest free cell.
inline constexpr double kSnapRadius = 2.0;

struct WalkGrid {
    enum Flag : std::uint8_t { kFree = 1, kNearJamb = 2, kConnector = 4 };

    GridOptions options;
    Point origin;  // lower-left corner of cell 0
    int cols = 0;
    int rows = 0;
    std::vector<std::uint8_t> flags;        // Flag bits per cell
    std::vector<std::uint8_t> moves;        // bit d: the step in direction d stays legal
    std::vector<std::int32_t> space;        // first space whose polygon holds the centre, −1: none
    std::vector<Segment> walls;             // walls cut at the widened door gaps, and the outline
    std::vector<Segment> jambs;             // wall next to a door that clearance ignores
    std::vector<std::int32_t> connector_cell;  // per plan connector: its free cell, −1: none within kSnapRadius
    // Square buckets of bucket_m listing the walls (index i) and jambs (walls.size() + j) near
    // them, for the exact tests below.
    double bucket_m = 2.0;
    int bucket_cols = 0, bucket_rows = 0;
    std::vector<std::vector<std::uint32_t>> buckets;

    int cell_count() const { return cols * rows; }
    bool free(int cell) const { return (flags[static_cast<std::size_t>(cell)] & kFree) != 0; }
    Point centre(int cell) const;
    int cell_at(Point p) const;  // −1 outside the grid
    // Whether ab crosses a wall or a jamb (exact).
    bool crosses_barrier(Point a, Point b) const;
    // Whether ab crosses no jamb and stays at least options.clearance from every wall (exact).
    bool keeps_clearance(Point a, Point b) const;
    // Indices (as in buckets) of every wall and jamb within bucket_m / 2 of ab, sorted, once each.
    std::vector<std::uint32_t> barriers_near(Point a, Point b) const;
    // The free cell nearest p within kSnapRadius, skipping cells flagged in `blocked` (when
    // given) and, with straight_line, cells whose centre p cannot see past a barrier; −1: none.
    int snap(Point p, const std::vector<std::uint8_t>* blocked, bool straight_line) const;
    // Distance below which a cell centre is blocked: clearance plus half a diagonal step.
    double clearance_threshold() const;
    // Clearance distance is measured as if each door gap were at least this wide (radius).
    double door_clear_radius() const;
};

// Expects a plan that passes check_plan (unchecked plans give a grid, not a meaningful one).
WalkGrid build_walk_grid(const Plan& plan, const GridOptions& options = {});

// The number of cells build_walk_grid gives the plan, without building it (a bounding box
// over all of the plan's points); doubles, so a plan past int's cells still counts.
double walk_grid_cells(const Plan& plan, const GridOptions& options = {});

}  // namespace locus::plan
