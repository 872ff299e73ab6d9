#include "locus/ranging/propagation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace locus::ranging {

WallIndex::WallIndex(std::vector<Segment> walls, double cell) : walls_(std::move(walls)), cell_(cell > 0 ? cell : 2.0) {
    stamp_.assign(walls_.size(), 0);
    if (walls_.empty()) return;
    double x1 = walls_[0].a.x, y1 = walls_[0].a.y;
    x0_ = x1;
    y0_ = y1;
    for (const auto& w : walls_)
        for (const Point p : {w.a, w.b}) {
            x0_ = std::min(x0_, p.x);
            y0_ = std::min(y0_, p.y);
            x1 = std::max(x1, p.x);
            y1 = std::max(y1, p.y);
        }
    // At most 512 cells a side: a huge site gets coarser cells, never a huge table.
    cell_ = std::max(cell_, std::max(x1 - x0_, y1 - y0_) / 512.0);
    nx_ = static_cast<int>((x1 - x0_) / cell_) + 1;
    ny_ = static_cast<int>((y1 - y0_) / cell_) + 1;
    cells_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_), {});
    for (std::size_t i = 0; i < walls_.size(); ++i) {
        const auto& w = walls_[i];
        // Every cell of the wall's bounding box: walls are short or axis-aligned in practice.
        const int cx0 = static_cast<int>((std::min(w.a.x, w.b.x) - x0_) / cell_), cx1 = static_cast<int>((std::max(w.a.x, w.b.x) - x0_) / cell_);
        const int cy0 = static_cast<int>((std::min(w.a.y, w.b.y) - y0_) / cell_), cy1 = static_cast<int>((std::max(w.a.y, w.b.y) - y0_) / cell_);
        for (int cx = cx0; cx <= cx1; ++cx)
            for (int cy = cy0; cy <= cy1; ++cy)
                cells_[static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(cx)].push_back(static_cast<int>(i));
    }
}

int WallIndex::crossed(Point a, Point b) const {
    if (walls_.empty()) return 0;
    if (++query_ == 0) {  // the stamps wrapped: start again
        std::fill(stamp_.begin(), stamp_.end(), 0u);
        query_ = 1;
    }
    int count = 0;
    auto test_cell = [&](int cx, int cy) {
        if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) return;
        for (int i : cells_[static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(cx)]) {
            if (stamp_[static_cast<std::size_t>(i)] == query_) continue;
            stamp_[static_cast<std::size_t>(i)] = query_;
            const auto& w = walls_[static_cast<std::size_t>(i)];
            if (segments_intersect(a, b, w.a, w.b)) ++count;
        }
    };
    // Walk the cells the segment crosses (Amanatides–Woo), in cell units.
    const double ax = (a.x - x0_) / cell_, ay = (a.y - y0_) / cell_, bx = (b.x - x0_) / cell_, by = (b.y - y0_) / cell_;
    int cx = static_cast<int>(std::floor(ax)), cy = static_cast<int>(std::floor(ay));
    const int ex = static_cast<int>(std::floor(bx)), ey = static_cast<int>(std::floor(by));
    const double dx = bx - ax, dy = by - ay;
    const int sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    const double tdx = dx != 0 ? std::fabs(1.0 / dx) : inf, tdy = dy != 0 ? std::fabs(1.0 / dy) : inf;
    double tx = dx != 0 ? ((sx > 0 ? std::floor(ax) + 1 - ax : ax - std::floor(ax)) * tdx) : inf;
    double ty = dy != 0 ? ((sy > 0 ? std::floor(ay) + 1 - ay : ay - std::floor(ay)) * tdy) : inf;
    test_cell(cx, cy);
    for (int guard = 0; (cx != ex || cy != ey) && guard < 4 * (nx_ + ny_) + 8; ++guard) {
        if (tx < ty) {
            tx += tdx;
            cx += sx;
        } else {
            ty += tdy;
            cy += sy;
        }
        test_cell(cx, cy);
        // A wall lying on a cell boundary is in the neighbour's list too: test it when the
        // path runs along that boundary (both steps at once).
        if (std::fabs(tx - ty) < 1e-12) {
            test_cell(cx + sx, cy);
            test_cell(cx, cy + sy);
        }
    }
    return count;
}

std::vector<ModelledReading> modelled_rss(Point at, std::span<const ModelledTransmitter> txs, const WallIndex& walls,
                                          double min_rss) {
    std::vector<ModelledReading> out;
    for (std::size_t i = 0; i < txs.size(); ++i) {
        const auto& t = txs[i];
        const double d = std::hypot(std::hypot(at.x - t.tx.at.x, at.y - t.tx.at.y), t.tx.dz);
        double rss = rss_at(t.tx.model, d);
        if (rss < min_rss) continue;  // walls only lower it further
        if (t.wall_attenuation && *t.wall_attenuation > 0) {
            // The path stops 1 cm short of the transmitter: one mounted on a wall is not behind it.
            const double flat = std::hypot(at.x - t.tx.at.x, at.y - t.tx.at.y);
            const double f = flat > 0.01 ? 0.01 / flat : 0.0;
            const Point end{t.tx.at.x + (at.x - t.tx.at.x) * f, t.tx.at.y + (at.y - t.tx.at.y) * f};
            rss -= *t.wall_attenuation * walls.crossed(at, end);
        }
        if (rss < min_rss) continue;
        out.push_back({i, std::min(rss, 0.0)});
    }
    return out;
}

std::vector<Point> grid_points(const Rect& area, double step) {
    std::vector<Point> out;
    if (!(step > 0)) return out;
    for (double y = area.ymin + step / 2; y < area.ymax; y += step)
        for (double x = area.xmin + step / 2; x < area.xmax; x += step) out.push_back({x, y});
    return out;
}

}  // namespace locus::ranging
