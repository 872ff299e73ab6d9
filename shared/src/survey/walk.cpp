#include "locus/survey/walk.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace locus::survey {

namespace {

void check_order(const std::vector<Landmark>& landmarks) {
    if (landmarks.empty()) throw std::invalid_argument("a walk needs at least one landmark");
    for (std::size_t i = 1; i < landmarks.size(); ++i)
        if (!(landmarks[i].t >= landmarks[i - 1].t))
            throw std::invalid_argument("landmarks are not in time order (landmark " + std::to_string(i + 1) +
                                        " is earlier than the one before it)");
}

// Path length up to each landmark and the span each belongs to.
struct Prefix {
    std::vector<double> path_m;
    std::vector<std::size_t> span;
};

Prefix prefix_of(const std::vector<Landmark>& landmarks) {
    Prefix p;
    p.path_m.resize(landmarks.size(), 0.0);
    p.span.resize(landmarks.size(), 0);
    for (std::size_t i = 1; i < landmarks.size(); ++i) {
        const bool same = landmarks[i].floor == landmarks[i - 1].floor;
        p.path_m[i] = p.path_m[i - 1] + (same ? distance(landmarks[i - 1].at, landmarks[i].at) : 0.0);
        p.span[i] = p.span[i - 1] + (same ? 0 : 1);
    }
    return p;
}

Placement place_with(const std::vector<Landmark>& landmarks, const Prefix& prefix, double t) {
    Placement out;
    if (t < landmarks.front().t) {
        out.why = Unplaced::before_first;
        return out;
    }
    if (t > landmarks.back().t) {
        out.why = Unplaced::after_last;
        return out;
    }
    // The last landmark at or before t.
    const auto it = std::upper_bound(landmarks.begin(), landmarks.end(), t,
                                     [](double v, const Landmark& l) { return v < l.t; });
    const std::size_t i = static_cast<std::size_t>(it - landmarks.begin()) - 1;
    const Landmark& a = landmarks[i];
    if (t == a.t || i + 1 == landmarks.size()) {
        out.position = WalkPosition{a.floor, a.at, prefix.path_m[i], prefix.span[i]};
        return out;
    }
    const Landmark& b = landmarks[i + 1];
    if (a.floor != b.floor) {
        out.why = Unplaced::floor_change;
        return out;
    }
    const double f = (t - a.t) / (b.t - a.t);
    const Point at{a.at.x + f * (b.at.x - a.at.x), a.at.y + f * (b.at.y - a.at.y)};
    out.position = WalkPosition{a.floor, at, prefix.path_m[i] + f * (prefix.path_m[i + 1] - prefix.path_m[i]), prefix.span[i]};
    return out;
}

}  // namespace

Placement place(const std::vector<Landmark>& landmarks, double t) {
    check_order(landmarks);
    return place_with(landmarks, prefix_of(landmarks), t);
}

WalkPlacements place_scans(const std::vector<Landmark>& landmarks, const std::vector<double>& scan_times) {
    check_order(landmarks);
    const Prefix prefix = prefix_of(landmarks);
    WalkPlacements out;
    for (std::size_t i = 0; i < scan_times.size(); ++i) {
        const Placement p = place_with(landmarks, prefix, scan_times[i]);
        if (p.position) {
            out.placed.push_back({i, scan_times[i], *p.position});
        } else if (*p.why == Unplaced::before_first) {
            ++out.before_first;
        } else if (*p.why == Unplaced::after_last) {
            ++out.after_last;
        } else {
            ++out.floor_change;
        }
    }
    return out;
}

std::vector<Bin> bin_along_path(const std::vector<PositionedScan>& placed, double cell_m) {
    if (!std::isfinite(cell_m) || cell_m < 0) throw std::invalid_argument("the cell must be a finite length >= 0");
    std::vector<Bin> bins;
    double first_path = 0.0;
    std::size_t span = 0;
    for (std::size_t i = 0; i < placed.size(); ++i) {
        const WalkPosition& w = placed[i].where;
        const bool joins = !bins.empty() && cell_m > 0 && w.floor == bins.back().floor && w.span == span &&
                           std::abs(w.path_m - first_path) <= cell_m;
        if (!joins) {
            bins.push_back(Bin{w.floor, {}, {}});
            first_path = w.path_m;
            span = w.span;
        }
        bins.back().members.push_back(i);
    }
    for (auto& b : bins) {
        double sx = 0.0, sy = 0.0;
        for (auto m : b.members) {
            sx += placed[m].where.at.x;
            sy += placed[m].where.at.y;
        }
        const double n = static_cast<double>(b.members.size());
        b.at = Point{sx / n, sy / n};
    }
    return bins;
}

}  // namespace locus::survey
