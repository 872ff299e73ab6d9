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
// a move passes are found with the same micrometre of slack. Most cells list none; one on a
// wall lists one or two.
//
// Cost: building, O(cells + Σ barrier length × margin / cell²); crosses(), the cells the move
// passes (≈ 2 × its length / cell) plus one segment test per barrier listed in them; near(), the
// barriers of one cell. Memory: memory_bytes().
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
    // Whether some barrier is within d of p (d at most margin()); p off the grid: any barrier
    // within d, tested against all of them.
    bool near(Point p, double d) const;
    // The barriers cell `cell` lists (copies, so a cell's walls are read from one place).
    const Segment* begin(int cell) const { return listed_.data() + first_[static_cast<std::size_t>(cell)]; }
    const Segment* end(int cell) const { return listed_.data() + first_[static_cast<std::size_t>(cell) + 1]; }
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
    std::vector<Segment> listed_;
    std::vector<std::uint32_t> outer_;  // barriers reaching off the grid, which no cell lists there
};

}  // namespace locus::plan
