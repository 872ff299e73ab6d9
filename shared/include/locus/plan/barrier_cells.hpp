#pragma once
// The walk grid's barriers (walls minus door gaps, jambs, the spaces' outline: walk_grid.hpp)
// listed per cell of the same grid, for tests whose cost must not grow with the plan: a move
// is checked only against the barriers in the cells it passes, a point only against those in
// its own cell. Built once per plan (map matching shares one per floor between every track on
// it) and immutable after.
//
// Each cell lists every barrier that comes within `margin` (plus a micrometre for rounding) of
// some point of the cell, so both answers below are exact, the same as testing every barrier:
// a move crossing a barrier crosses it at a point of some cell the move passes, and the cells
// a move passes are found with the same micrometre of slack. With a small margin (0.1 m) most
// cells list none and one on a wall lists one or two. With a step's length as the margin, a
// move no longer than it meets only barriers its start cell lists (crosses_from): one list
// instead of the cells it passes, for longer lists (on the PUTMC plan, 8 a cell at 1 m).
//
// Cost: building, O(cells + Σ barrier length × margin / cell²); crosses(), the cells the move
// passes (≈ 2 × its length / cell) plus one segment test per barrier listed in them;
// crosses_from() and near(), the barriers of one cell. Memory: memory_bytes() (a uint32 per
// cell and per listed barrier, and the barriers once).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/plan/walk_grid.hpp"

namespace locus::plan {

class BarrierCells {
public:
    BarrierCells() = default;
    // The grid's walls and jambs (in WalkGrid::buckets' order) over the grid's own cells.
    BarrierCells(const WalkGrid& grid, double margin);

    double margin() const { return margin_; }
    // Whether ab crosses (touches) a barrier: grid.crosses_barrier(a, b) exactly.
    bool crosses(Point a, Point b) const;
    // crosses(a, b) for a in cell `cell` (≥ 0) and |ab| ≤ margin(): every barrier the move can
    // touch is within margin of a, so listed in a's cell.
    bool crosses_from(int cell, Point a, Point b) const { return crosses_in(cell, a, b); }
    // Whether some barrier is within d of p (d at most margin()); p off the grid: any barrier
    // within d, tested against all of them.
    bool near(Point p, double d) const;
    std::size_t barrier_count() const { return barriers_.size(); }
    std::size_t entries() const { return listed_.size(); }  // Σ over cells of the barriers listed
    std::size_t memory_bytes() const;

private:
    bool crosses_in(int cell, Point a, Point b) const;

    Point origin_;
    double cell_ = 1.0, inv_cell_ = 1.0;
    int cols_ = 0, rows_ = 0;
    double margin_ = 0.0;
    std::vector<Segment> barriers_;     // walls then jambs
    std::vector<std::uint32_t> first_;  // per cell, where its list starts in listed_; one more at the end
    std::vector<std::uint32_t> listed_;  // indices into barriers_
    std::vector<std::uint32_t> outer_;  // barriers reaching off the grid, which no cell lists there
};

}  // namespace locus::plan
