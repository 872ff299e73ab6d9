#include "locus/floor_places.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace locus {

namespace {

// A rectangle that can hold a point: finite, not inverted (a stored room's always is).
bool usable(const Rect& r) {
    return std::isfinite(r.xmin) && std::isfinite(r.ymin) && std::isfinite(r.xmax) && std::isfinite(r.ymax) && r.xmin <= r.xmax &&
           r.ymin <= r.ymax;
}

}  // namespace

FloorPlaces::FloorPlaces(std::vector<Room> rooms, std::vector<Poi> pois) : rooms_(std::move(rooms)), pois_(std::move(pois)) {
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    std::size_t rects = 0;
    for (const auto& room : rooms_)
        for (const auto& r : room.rects) {
            if (!usable(r)) continue;
            x0 = std::min(x0, r.xmin), y0 = std::min(y0, r.ymin), x1 = std::max(x1, r.xmax), y1 = std::max(y1, r.ymax);
            ++rects;
        }
    first_.assign(1, 0);
    if (rects == 0) return;
    // About one cell per rectangle, square cells, never more than kMaxCells.
    const double w = std::max(x1 - x0, 1e-6), h = std::max(y1 - y0, 1e-6);
    cell_ = std::max(std::sqrt(w * h / static_cast<double>(rects)), std::sqrt(w * h / static_cast<double>(kMaxCells)));
    cell_ = std::max(cell_, 1e-3);
    cols_ = std::max(1, static_cast<int>(std::ceil(w / cell_)));
    rows_ = std::max(1, static_cast<int>(std::ceil(h / cell_)));
    while (static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_) > kMaxCells) {
        cell_ *= 1.5;
        cols_ = std::max(1, static_cast<int>(std::ceil(w / cell_)));
        rows_ = std::max(1, static_cast<int>(std::ceil(h / cell_)));
    }
    origin_ = {x0, y0};
    const std::size_t cells = static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_);
    // Each cell's rooms in the rooms' order, each once, then flattened.
    std::vector<std::vector<std::uint32_t>> lists(cells);
    const auto clamp_col = [&](double x) { return std::clamp(static_cast<int>(std::floor((x - origin_.x) / cell_)), 0, cols_ - 1); };
    const auto clamp_row = [&](double y) { return std::clamp(static_cast<int>(std::floor((y - origin_.y) / cell_)), 0, rows_ - 1); };
    for (std::size_t i = 0; i < rooms_.size(); ++i)
        for (const auto& r : rooms_[i].rects) {
            if (!usable(r)) continue;
            for (int row = clamp_row(r.ymin); row <= clamp_row(r.ymax); ++row)
                for (int col = clamp_col(r.xmin); col <= clamp_col(r.xmax); ++col) {
                    auto& list = lists[static_cast<std::size_t>(row) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(col)];
                    if (list.empty() || list.back() != i) list.push_back(static_cast<std::uint32_t>(i));
                }
        }
    first_.assign(cells + 1, 0);
    for (std::size_t c = 0; c < cells; ++c) first_[c + 1] = first_[c] + static_cast<std::uint32_t>(lists[c].size());
    room_index_.reserve(first_.back());
    for (const auto& list : lists) room_index_.insert(room_index_.end(), list.begin(), list.end());
}

int FloorPlaces::cell_of(Point p) const {
    if (cols_ == 0) return -1;
    const double fc = (p.x - origin_.x) / cell_, fr = (p.y - origin_.y) / cell_;
    if (!(fc >= 0.0 && fr >= 0.0 && fc <= cols_ && fr <= rows_)) return -1;
    // A point on the box's far edge belongs to the last cell (rectangles are closed).
    const int col = std::min(static_cast<int>(fc), cols_ - 1), row = std::min(static_cast<int>(fr), rows_ - 1);
    return row * cols_ + col;
}

const Room* FloorPlaces::room_at(Point p) const {
    const int c = cell_of(p);
    if (c < 0) return nullptr;
    for (std::uint32_t k = first_[static_cast<std::size_t>(c)]; k < first_[static_cast<std::size_t>(c) + 1]; ++k) {
        const Room& room = rooms_[room_index_[k]];
        if (room.contains(p)) return &room;
    }
    return nullptr;
}

std::vector<NearbyPoi> FloorPlaces::nearby(Point p, double radius_m) const {
    std::vector<NearbyPoi> out;
    // Squared distances first: the root only for the few within the radius.
    const double r2 = radius_m * radius_m;
    for (const auto& poi : pois_) {
        const double dx = poi.at.x - p.x, dy = poi.at.y - p.y;
        if (dx * dx + dy * dy <= r2 * (1.0 + 1e-12)) {
            if (const double d = distance(poi.at, p); d <= radius_m) out.push_back({&poi, d});
        }
    }
    std::sort(out.begin(), out.end(), [](const NearbyPoi& a, const NearbyPoi& b) {
        return a.distance_m != b.distance_m ? a.distance_m < b.distance_m : a.poi->id < b.poi->id;
    });
    return out;
}

std::size_t FloorPlaces::memory_bytes() const {
    std::size_t n = sizeof(*this) + first_.capacity() * sizeof(std::uint32_t) + room_index_.capacity() * sizeof(std::uint32_t);
    for (const auto& r : rooms_) n += sizeof(Room) + r.name.capacity() + r.rects.capacity() * sizeof(Rect);
    for (const auto& p : pois_) n += sizeof(Poi) + p.name.capacity() + p.kind.capacity();
    return n;
}

}  // namespace locus
