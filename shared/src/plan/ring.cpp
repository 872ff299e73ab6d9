#include "locus/plan/ring.hpp"

#include <algorithm>
#include <vector>

namespace locus::plan {

double signed_area(const Ring& ring) {
    double twice = 0.0;
    for (std::size_t i = 0; i + 1 < ring.size(); ++i)
        twice += ring[i].x * ring[i + 1].y - ring[i + 1].x * ring[i].y;
    if (!ring.empty()) twice += ring.back().x * ring.front().y - ring.front().x * ring.back().y;
    return twice / 2.0;
}

bool ring_contains(const Ring& ring, Point p) {
    bool inside = false;
    const std::size_t n = ring.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        const Point a = ring[i], b = ring[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
    }
    return inside;
}

bool polygon_contains(const Polygon& polygon, Point p) {
    if (!ring_contains(polygon.outer, p)) return false;
    return std::none_of(polygon.holes.begin(), polygon.holes.end(), [&](const Ring& h) { return ring_contains(h, p); });
}

namespace {

// Area-weighted centroid of the ring; the mean of its points when it has no area.
Point centroid(const Ring& ring) {
    double a = 0.0, cx = 0.0, cy = 0.0;
    for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
        const Point p = ring[i], q = ring[(i + 1) % n];
        const double cross = p.x * q.y - q.x * p.y;
        a += cross;
        cx += (p.x + q.x) * cross;
        cy += (p.y + q.y) * cross;
    }
    if (a != 0.0) return {cx / (3.0 * a), cy / (3.0 * a)};
    Point mean;
    for (const Point& p : ring) mean = {mean.x + p.x / static_cast<double>(ring.size()), mean.y + p.y / static_cast<double>(ring.size())};
    return mean;
}

// Where the line at height y crosses the polygon's edges, left to right.
std::vector<double> crossings(const Polygon& polygon, double y) {
    std::vector<double> xs;
    const auto add = [&](const Ring& ring) {
        for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
            const Point a = ring[i], b = ring[j];
            if ((a.y > y) != (b.y > y)) xs.push_back((b.x - a.x) * (y - a.y) / (b.y - a.y) + a.x);
        }
    };
    add(polygon.outer);
    for (const Ring& h : polygon.holes) add(h);
    std::sort(xs.begin(), xs.end());
    return xs;
}

}  // namespace

Point interior_point(const Polygon& polygon) {
    if (polygon.outer.empty()) return {};
    const Point c = centroid(polygon.outer);
    if (polygon_contains(polygon, c)) return c;
    const Bounds b = bounds_of(polygon.outer);
    // The centroid's height first, then heights spread over the bounds.
    const double fractions[] = {0.5, 0.25, 0.75, 0.125, 0.375, 0.625, 0.875};
    std::vector<double> heights{c.y};
    for (const double f : fractions) heights.push_back(b.ymin + f * (b.ymax - b.ymin));
    for (const double y : heights) {
        const auto xs = crossings(polygon, y);
        double widest = 0.0;
        Point best;
        for (std::size_t i = 0; i + 1 < xs.size(); i += 2)
            if (xs[i + 1] - xs[i] > widest) {
                widest = xs[i + 1] - xs[i];
                best = {(xs[i] + xs[i + 1]) / 2.0, y};
            }
        if (widest > 0.0 && polygon_contains(polygon, best)) return best;
    }
    return polygon.outer.front();  // a sliver: its corner is as close as it gets
}

Bounds bounds_of(const Ring& ring) {
    if (ring.empty()) return {};
    Bounds b{ring[0].x, ring[0].y, ring[0].x, ring[0].y};
    for (const Point& p : ring) {
        b.xmin = std::min(b.xmin, p.x);
        b.ymin = std::min(b.ymin, p.y);
        b.xmax = std::max(b.xmax, p.x);
        b.ymax = std::max(b.ymax, p.y);
    }
    return b;
}

}  // namespace locus::plan
