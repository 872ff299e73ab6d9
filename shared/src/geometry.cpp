#include "locus/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace locus {

double distance(Point a, Point b) { return std::hypot(a.x - b.x, a.y - b.y); }

namespace {

double cross(Point o, Point a, Point b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

bool on_segment(Point p, Point a, Point b) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

int sign(double v) { return (v > 0.0) - (v < 0.0); }

}  // namespace

bool segments_intersect(Point p, Point q, Point a, Point b) {
    const int d1 = sign(cross(a, b, p));
    const int d2 = sign(cross(a, b, q));
    const int d3 = sign(cross(p, q, a));
    const int d4 = sign(cross(p, q, b));
    if (d1 * d2 < 0 && d3 * d4 < 0) return true;
    if (d1 == 0 && on_segment(p, a, b)) return true;
    if (d2 == 0 && on_segment(q, a, b)) return true;
    if (d3 == 0 && on_segment(a, p, q)) return true;
    if (d4 == 0 && on_segment(b, p, q)) return true;
    return false;
}

double distance_to_segment(Point p, Point a, Point b) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double len2 = dx * dx + dy * dy;
    if (len2 == 0.0) return distance(p, a);
    const double t = std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0);
    return distance(p, {a.x + t * dx, a.y + t * dy});
}

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
