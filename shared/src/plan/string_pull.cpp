#include "string_pull.hpp"

#include <algorithm>
#include <cmath>

namespace locus::plan {

bool clear_line(const WalkGrid& grid, const std::vector<std::uint8_t>* blocked, Point a, Point b) {
    // Walkable and not avoided: sampled every half cell. Clearance: exact.
    const double step = grid.options.cell / 2.0;
    const int n = std::max(1, static_cast<int>(std::ceil(distance(a, b) / step)));
    for (int i = 0; i <= n; ++i) {
        const double t = static_cast<double>(i) / n;
        const int cell = grid.cell_at({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
        if (cell < 0 || grid.space[static_cast<std::size_t>(cell)] < 0) return false;
        if (blocked && (*blocked)[static_cast<std::size_t>(cell)]) return false;
    }
    return grid.keeps_clearance(a, b);
}

std::vector<Point> pull_string(const WalkGrid& grid, const std::vector<std::uint8_t>* blocked, const std::vector<Point>& path) {
    if (path.size() <= 2) return path;
    const std::size_t last = path.size() - 1;
    std::vector<Point> out{path.front()};
    std::size_t anchor = 0;
    const auto sees = [&](std::size_t i) { return clear_line(grid, blocked, path[anchor], path[i]); };
    while (anchor < last) {
        // Gallop forward while in sight, then bisect between the last seen and the first hidden
        // vertex. Sight along a path is nearly monotone; where it is not, a vertex too many is kept.
        std::size_t seen = anchor + 1, hidden = last + 1;
        for (std::size_t span = 2;; span *= 2) {
            const std::size_t probe = std::min(anchor + span, last);
            if (probe <= seen) break;
            if (!sees(probe)) {
                hidden = probe;
                break;
            }
            seen = probe;
            if (probe == last) break;
        }
        while (hidden <= last && hidden - seen > 1) {
            const std::size_t mid = seen + (hidden - seen) / 2;
            (sees(mid) ? seen : hidden) = mid;
        }
        out.push_back(path[seen]);
        anchor = seen;
    }
    return out;
}

}  // namespace locus::plan
