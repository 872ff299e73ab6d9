#include "locus/plan/barrier_cells.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace locus::plan {

namespace {

// Slack for rounding: a barrier this close to a cell is listed there, a move this close to a
// cell passes it.
constexpr double kSlack = 1e-6;

// ⌊v⌋ clamped to [0, count − 1] (NaN: 0), without floor: a truncation once v ≥ 0.
int index_of(double v, int count) {
    if (!(v >= 0.0)) return 0;
    return v < count - 1 ? static_cast<int>(v) : count - 1;
}

// distance_to_segment(p, a, b)², without its square root.
double distance2_to_segment(Point p, Point a, Point b) {
    const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    double t = len2 > 0.0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const double ex = a.x + t * dx - p.x, ey = a.y + t * dy - p.y;
    return ex * ex + ey * ey;
}

}  // namespace

BarrierCells::BarrierCells(const WalkGrid& grid, double margin)
    : origin_(grid.origin), cell_(grid.options.cell), inv_cell_(1.0 / grid.options.cell), cols_(grid.cols), rows_(grid.rows), margin_(margin) {
    barriers_.reserve(grid.walls.size() + grid.jambs.size());
    barriers_.insert(barriers_.end(), grid.walls.begin(), grid.walls.end());
    barriers_.insert(barriers_.end(), grid.jambs.begin(), grid.jambs.end());
    if (barriers_.size() >= std::numeric_limits<std::uint32_t>::max()) throw std::length_error("too many barriers for the cell lists");
    const std::size_t cells = static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_);
    // A barrier is listed in every cell whose centre is within margin plus half a diagonal of
    // it: every cell it comes within margin of, and a few more (harmless, only tested).
    const double reach = margin + cell_ * std::sqrt(0.5) + kSlack;
    const auto col = [&](double x) { return std::clamp(static_cast<int>(std::floor((x - origin_.x) / cell_)), 0, cols_ - 1); };
    const auto row = [&](double y) { return std::clamp(static_cast<int>(std::floor((y - origin_.y) / cell_)), 0, rows_ - 1); };
    const double xmax = origin_.x + cols_ * cell_, ymax = origin_.y + rows_ * cell_;
    const auto inside_grid = [&](Point p) { return p.x >= origin_.x && p.y >= origin_.y && p.x <= xmax && p.y <= ymax; };
    const auto each_cell = [&](const Segment& s, auto&& f) {
        for (int r = row(std::min(s.a.y, s.b.y) - reach); r <= row(std::max(s.a.y, s.b.y) + reach); ++r)
            for (int c = col(std::min(s.a.x, s.b.x) - reach); c <= col(std::max(s.a.x, s.b.x) + reach); ++c) {
                const Point centre{origin_.x + (c + 0.5) * cell_, origin_.y + (r + 0.5) * cell_};
                if (distance_to_segment(centre, s.a, s.b) <= reach) f(r * cols_ + c);
            }
    };
    // Two passes, counting then filling, so the lists are one array.
    first_.assign(cells + 1, 0);
    for (const Segment& s : barriers_) each_cell(s, [&](int c) { ++first_[static_cast<std::size_t>(c) + 1]; });
    for (std::size_t c = 0; c < cells; ++c) first_[c + 1] += first_[c];
    listed_.resize(first_[cells]);
    std::vector<std::uint32_t> fill(first_.begin(), first_.end() - 1);
    for (std::uint32_t i = 0; i < barriers_.size(); ++i) {
        each_cell(barriers_[i], [&](int c) { listed_[fill[static_cast<std::size_t>(c)]++] = i; });
        // Off the grid no cell lists it: a move that leaves the grid tests it directly.
        if (!inside_grid(barriers_[i].a) || !inside_grid(barriers_[i].b)) outer_.push_back(i);
    }
    // Nearest the cell's centre first: a blocked move is most often stopped by the nearest
    // wall, and the test ends at the first barrier crossed.
    for (std::size_t c = 0; c < cells; ++c) {
        const Point centre{origin_.x + (static_cast<double>(c % static_cast<std::size_t>(cols_)) + 0.5) * cell_,
                           origin_.y + (static_cast<double>(c / static_cast<std::size_t>(cols_)) + 0.5) * cell_};
        const auto d = [&](std::uint32_t i) { return distance2_to_segment(centre, barriers_[i].a, barriers_[i].b); };
        std::sort(listed_.begin() + first_[c], listed_.begin() + first_[c + 1],
                  [&](std::uint32_t i, std::uint32_t j) { return d(i) < d(j) || (d(i) == d(j) && i < j); });
    }
}

bool BarrierCells::crosses_in(int cell, Point a, Point b) const {
    // Segments that share a point have overlapping (closed) boxes: most listed walls fail that
    // cheaper test first.
    const double x0 = std::min(a.x, b.x), x1 = std::max(a.x, b.x), y0 = std::min(a.y, b.y), y1 = std::max(a.y, b.y);
    for (std::uint32_t k = first_[static_cast<std::size_t>(cell)]; k < first_[static_cast<std::size_t>(cell) + 1]; ++k) {
        const Segment* s = &barriers_[listed_[k]];
        if (std::max(s->a.x, s->b.x) < x0 || std::min(s->a.x, s->b.x) > x1 || std::max(s->a.y, s->b.y) < y0 || std::min(s->a.y, s->b.y) > y1)
            continue;
        if (segments_intersect(a, b, s->a, s->b)) return true;
    }
    return false;
}

bool BarrierCells::crosses(Point a, Point b) const {
    if (cols_ <= 0 || rows_ <= 0) return false;
    const double xmax = origin_.x + cols_ * cell_, ymax = origin_.y + rows_ * cell_;
    const auto off = [&](Point p) { return !(p.x >= origin_.x && p.y >= origin_.y && p.x <= xmax && p.y <= ymax); };
    if (off(a) || off(b))
        for (std::uint32_t i : outer_)
            if (segments_intersect(a, b, barriers_[i].a, barriers_[i].b)) return true;
    const auto col = [&](double x) { return index_of((x - origin_.x) * inv_cell_, cols_); };
    const auto row = [&](double y) { return index_of((y - origin_.y) * inv_cell_, rows_); };
    const double x0 = std::min(a.x, b.x), x1 = std::max(a.x, b.x);
    const double dx = b.x - a.x, dy = b.y - a.y;
    // Column by column: the rows the move spans within each column's strip (both ends of the
    // strip, a micrometre wider), so no cell it touches is missed.
    const int c0 = col(x0 - kSlack), c1 = col(x1 + kSlack);
    for (int c = c0; c <= c1; ++c) {
        double ylo, yhi;
        if (c0 == c1 || dx == 0.0) {
            ylo = std::min(a.y, b.y);
            yhi = std::max(a.y, b.y);
        } else {
            const double sx0 = std::max(x0, c == c0 ? x0 : origin_.x + c * cell_ - kSlack);
            const double sx1 = std::min(x1, c == c1 ? x1 : origin_.x + (c + 1) * cell_ + kSlack);
            const double ya = a.y + (sx0 - a.x) * dy / dx, yb = a.y + (sx1 - a.x) * dy / dx;
            ylo = std::min(ya, yb);
            yhi = std::max(ya, yb);
        }
        const int r0 = row(ylo - kSlack), r1 = row(yhi + kSlack);
        for (int r = r0; r <= r1; ++r)
            if (crosses_in(r * cols_ + c, a, b)) return true;
    }
    return false;
}

bool BarrierCells::near(Point p, double d) const {
    const double fc = (p.x - origin_.x) * inv_cell_, fr = (p.y - origin_.y) * inv_cell_;
    if (fc >= 0.0 && fr >= 0.0 && fc < cols_ && fr < rows_ && d <= margin_) {
        const int cell = static_cast<int>(fr) * cols_ + static_cast<int>(fc);
        for (std::uint32_t k = first_[static_cast<std::size_t>(cell)]; k < first_[static_cast<std::size_t>(cell) + 1]; ++k) {
            const Segment* s = &barriers_[listed_[k]];
            // Farther than d from the wall's box is farther than d from the wall.
            if (std::max(s->a.x, s->b.x) < p.x - d || std::min(s->a.x, s->b.x) > p.x + d || std::max(s->a.y, s->b.y) < p.y - d ||
                std::min(s->a.y, s->b.y) > p.y + d)
                continue;
            if (distance2_to_segment(p, s->a, s->b) <= d * d) return true;
        }
        return false;
    }
    return std::any_of(barriers_.begin(), barriers_.end(), [&](const Segment& s) { return distance_to_segment(p, s.a, s.b) <= d; });
}

std::size_t BarrierCells::memory_bytes() const {
    return sizeof(*this) + barriers_.capacity() * sizeof(Segment) + first_.capacity() * sizeof(std::uint32_t) +
           listed_.capacity() * sizeof(std::uint32_t) + outer_.capacity() * sizeof(std::uint32_t);
}

}  // namespace locus::plan
