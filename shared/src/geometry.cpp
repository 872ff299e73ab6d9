#include "locus/geometry.hpp"

#include <cmath>
#include <stdexcept>

namespace locus {

double distance(Point a, Point b) { return std::hypot(a.x - b.x, a.y - b.y); }

bool Rect::contains(Point p) const {
    return p.x >= xmin && p.x <= xmax && p.y >= ymin && p.y <= ymax;
}

double Rect::area() const { return (xmax - xmin) * (ymax - ymin); }

Point Rect::centre() const { return {(xmin + xmax) / 2.0, (ymin + ymax) / 2.0}; }

bool Room::contains(Point p) const {
    for (const auto& r : rects)
        if (r.contains(p)) return true;
    return false;
}

double Room::area() const {
    double a = 0.0;
    for (const auto& r : rects) a += r.area();
    return a;
}

Point Room::centre() const {
    double a = 0.0, cx = 0.0, cy = 0.0;
    for (const auto& r : rects) {
        const double ra = r.area();
        const Point c = r.centre();
        a += ra;
        cx += ra * c.x;
        cy += ra * c.y;
    }
    if (a <= 0.0) return rects.empty() ? Point{} : rects.front().centre();
    return {cx / a, cy / a};
}

const Room* room_at(const std::vector<Room>& rooms, Point p) {
    for (const auto& room : rooms)
        if (room.contains(p)) return &room;
    return nullptr;
}

const Room* FloorPlan::room_at(Point p) const { return locus::room_at(rooms, p); }

std::vector<const Poi*> FloorPlan::pois_near(Point p, double radius) const {
    std::vector<const Poi*> out;
    for (const auto& poi : pois)
        if (distance(poi.at, p) <= radius) out.push_back(&poi);
    return out;
}

bool FloorPlan::inside_bounds(Point p) const {
    return p.x >= 0.0 && p.y >= 0.0 && p.x <= width && p.y <= height;
}

long long reference_points_needed(double area_m2, double cell_m) {
    if (!(cell_m > 0.0) || !(area_m2 >= 0.0)) throw std::invalid_argument("area must be >= 0 and cell > 0");
    return static_cast<long long>(std::ceil(area_m2 / (cell_m * cell_m)));
}

}  // namespace locus
