#include "locus/plan/rects.hpp"

#include <algorithm>
#include <cmath>

namespace locus::plan {

namespace {

// Sorted disjoint intervals reduced to at most `max` by joining neighbours across the
// narrowest gaps, in linear time for any count.
std::vector<std::pair<double, double>> at_most(std::vector<std::pair<double, double>> in, std::size_t max) {
    if (in.size() <= max) return in;
    std::vector<std::pair<double, std::size_t>> gaps;  // (width, index of the gap above interval i)
    for (std::size_t i = 0; i + 1 < in.size(); ++i) gaps.emplace_back(in[i + 1].first - in[i].second, i);
    const std::size_t joins = in.size() - max;
    std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(joins - 1), gaps.end());
    std::vector<bool> join(in.size(), false);
    for (std::size_t g = 0; g < joins; ++g) join[gaps[g].second] = true;
    std::vector<std::pair<double, double>> out;
    for (std::size_t i = 0; i < in.size(); ++i) {
        if (i > 0 && join[i - 1]) out.back().second = in[i].second;
        else out.push_back(in[i]);
    }
    return out;
}

// The covered y-intervals at x: crossings of every ring's non-vertical edges, paired up.
std::vector<std::pair<double, double>> intervals_at(const Polygon& shape, double x) {
    std::vector<double> ys;
    const auto crossings = [&](const Ring& ring) {
        for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
            const Point a = ring[i], b = ring[i + 1];
            // Half-open in x so a vertex exactly at x counts once; slab middles never sit on a
            // vertex anyway, unless the cuts were thinned.
            if ((a.x <= x && x < b.x) || (b.x <= x && x < a.x)) ys.push_back(a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x));
        }
    };
    crossings(shape.outer);
    for (const auto& h : shape.holes) crossings(h);
    std::sort(ys.begin(), ys.end());
    std::vector<std::pair<double, double>> out;
    for (std::size_t i = 0; i + 1 < ys.size(); i += 2)
        if (ys[i + 1] > ys[i]) out.emplace_back(ys[i], ys[i + 1]);
    return at_most(std::move(out), kMaxSlabIntervals);
}

}  // namespace

std::vector<Rect> rects_of(const Polygon& shape) {
    std::vector<double> xs;
    const auto add = [&](const Ring& r) {
        for (const auto& p : r) xs.push_back(p.x);
    };
    add(shape.outer);
    for (const auto& h : shape.holes) add(h);
    std::sort(xs.begin(), xs.end());
    // x's a rounding apart (a curve's mirrored vertices, computed separately) would make
    // slabs of zero width: they count as one cut.
    xs.erase(std::unique(xs.begin(), xs.end(), [](double a, double b) { return b - a <= 1e-9 * std::max(1.0, std::abs(a)); }),
             xs.end());
    if (xs.size() < 2) return {};
    if (xs.size() > kMaxRoomSlabs + 1) {
        std::vector<double> thinned;
        for (std::size_t i = 0; i <= kMaxRoomSlabs; ++i) thinned.push_back(xs[i * (xs.size() - 1) / kMaxRoomSlabs]);
        xs = std::move(thinned);
    }

    std::vector<Rect> done, open;  // open: the previous slab's rectangles, still growing
    for (std::size_t s = 0; s + 1 < xs.size(); ++s) {
        const double x0 = xs[s], x1 = xs[s + 1];
        std::vector<Rect> next;
        for (const auto& interval : intervals_at(shape, (x0 + x1) / 2)) {
            const double y0 = interval.first, y1 = interval.second;  // named, not bound: lambdas capture them
            const auto same = std::find_if(open.begin(), open.end(),
                                           [&](const Rect& r) { return r.ymin == y0 && r.ymax == y1 && r.xmax == x0; });
            if (same != open.end()) {
                next.push_back({same->xmin, y0, x1, y1});
                open.erase(same);
            } else {
                next.push_back({x0, y0, x1, y1});
            }
        }
        done.insert(done.end(), open.begin(), open.end());
        open = std::move(next);
    }
    done.insert(done.end(), open.begin(), open.end());
    std::sort(done.begin(), done.end(), [](const Rect& a, const Rect& b) {
        return a.xmin != b.xmin ? a.xmin < b.xmin : a.ymin < b.ymin;
    });
    return done;
}

}  // namespace locus::plan
