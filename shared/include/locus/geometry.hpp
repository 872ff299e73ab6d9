#pragma once
// Floor geometry in the docs/spec.md §2.1 convention: metres, origin at the floor plan's lower-left
// corner, x to the right, y up.
#include <optional>
#include <string>
#include <vector>

namespace locus {

struct Point {
    double x = 0.0;
    double y = 0.0;
};

double distance(Point a, Point b);

struct Segment {
    Point a;
    Point b;
};

// True when segments pq and ab share a point (touching counts).
bool segments_intersect(Point p, Point q, Point a, Point b);

// Distance from p to the closed segment ab (to a itself when a == b).
double distance_to_segment(Point p, Point a, Point b);

struct Rect {
    double xmin = 0.0, ymin = 0.0, xmax = 0.0, ymax = 0.0;
    // Closed on all sides so a point on a shared wall belongs to a room rather than to none.
    bool contains(Point p) const;
    double area() const;
    Point centre() const;
};

struct Room {
    long long id = 0;
    std::string name;
    std::vector<Rect> rects;  // irregular rooms are unions of rectangles
    bool contains(Point p) const;
    double area() const;  // sum of rectangles; overlaps are the caller's business
    Point centre() const;  // area-weighted centroid of the rectangles
};

struct Poi {
    long long id = 0;
    std::string name;
    std::string kind;
    Point at;
};

// First room (in order) whose rectangles contain p; nullptr when none does.
const Room* room_at(const std::vector<Room>& rooms, Point p);

inline constexpr double kDefaultCheckpointRadius = 1.5;

struct FloorPlan {
    double width = 0.0;
    double height = 0.0;
    std::vector<Room> rooms;
    std::vector<Poi> pois;

    // First room (in declaration order) whose rectangles contain p.
    const Room* room_at(Point p) const;
    std::vector<const Poi*> pois_near(Point p, double radius = kDefaultCheckpointRadius) const;
    bool inside_bounds(Point p) const;
};

// docs/spec.md §3.1: RPs needed for a floor of area A with cell side c, ceil(A / c²).
long long reference_points_needed(double area_m2, double cell_m);

}  // namespace locus
