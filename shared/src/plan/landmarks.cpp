#include "locus/plan/landmarks.hpp"

#include <cmath>
#include <queue>

namespace locus::plan {

namespace {

std::vector<float> distances_from(const WalkGrid& grid, int source) {
    std::vector<float> metres(static_cast<std::size_t>(grid.cell_count()), kNoPath);
    if (source < 0) return metres;
    const float straight = static_cast<float>(grid.options.cell), diagonal = static_cast<float>(grid.options.cell * std::sqrt(2.0));
    using Entry = std::pair<float, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
    metres[static_cast<std::size_t>(source)] = 0.0f;
    open.push({0.0f, source});
    while (!open.empty()) {
        const auto [d, cell] = open.top();
        open.pop();
        if (d > metres[static_cast<std::size_t>(cell)]) continue;
        const std::uint8_t moves = grid.moves[static_cast<std::size_t>(cell)];
        for (int dir = 0; dir < 8; ++dir) {
            if (!(moves & (1u << dir))) continue;
            const int next = cell + kDirCol[dir] + kDirRow[dir] * grid.cols;
            const float nd = d + ((dir % 2) ? diagonal : straight);
            auto& slot = metres[static_cast<std::size_t>(next)];
            if (nd < slot) {
                slot = nd;
                open.push({nd, next});
            }
        }
    }
    return metres;
}

}  // namespace

Landmarks landmarks_from(const WalkGrid& grid, const std::vector<int>& sources) {
    Landmarks out{sources, std::vector<float>(static_cast<std::size_t>(grid.cell_count()) * sources.size())};
    for (std::size_t l = 0; l < sources.size(); ++l) {
        const std::vector<float> metres = distances_from(grid, sources[l]);
        for (std::size_t c = 0; c < metres.size(); ++c) out.metres[c * sources.size() + l] = metres[c];
    }
    return out;
}

std::vector<int> corner_cells(const WalkGrid& grid) {
    std::vector<int> out;
    const double w = grid.cols * grid.options.cell, h = grid.rows * grid.options.cell;
    for (const Point corner : {Point{0, 0}, Point{w, 0}, Point{0, h}, Point{w, h}}) {
        int best = -1;
        double best_d = INFINITY;
        for (int c = 0; c < grid.cell_count(); ++c) {
            if (!grid.free(c)) continue;
            const Point p = grid.centre(c);
            const double d = std::abs(p.x - grid.origin.x - corner.x) + std::abs(p.y - grid.origin.y - corner.y);
            if (d < best_d) {
                best_d = d;
                best = c;
            }
        }
        if (best >= 0) out.push_back(best);
    }
    return out;
}

}  // namespace locus::plan
