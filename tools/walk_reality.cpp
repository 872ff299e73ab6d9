#include "walk_reality.hpp"

#include <algorithm>
#include <cmath>

#include "locus/motion/pdr/heading_convention.hpp"

namespace locus::tools::walks {

namespace {

// φ per interval for one handedness of the compass; s = −1 mirrors it.
std::vector<std::pair<double, double>> rotations(const std::vector<PhoneStep>& steps, const std::vector<Point>& truth,
                                                 const std::vector<double>& scan_t, double s) {
    std::vector<std::pair<double, double>> out;  // (φ, metres walked up to the interval's end)
    double along = 0.0;
    for (std::size_t i = 1; i < truth.size(); ++i) {
        const double dx = truth[i].x - truth[i - 1].x, dy = truth[i].y - truth[i - 1].y;
        along += std::hypot(dx, dy);
        double px = 0.0, py = 0.0;
        for (const auto& st : steps)
            if (st.t_s > scan_t[i - 1] && st.t_s <= scan_t[i]) {
                px += s * st.length_m * std::sin(st.azimuth_rad);
                py += st.length_m * std::cos(st.azimuth_rad);
            }
        if (std::hypot(dx, dy) < 2.0 || std::hypot(px, py) < 1.0) continue;
        out.push_back({pdr::wrap_angle(std::atan2(dx, dy) - std::atan2(px, py)), along});
    }
    // Unwrap: each φ within π of the one before.
    for (std::size_t i = 1; i < out.size(); ++i)
        out[i].first = out[i - 1].first + pdr::wrap_angle(out[i].first - out[i - 1].first);
    return out;
}

double increment_sum_sq(const std::vector<std::pair<double, double>>& r, double* metres, std::size_t lag = 1) {
    double sum = 0.0;
    *metres = 0.0;
    for (std::size_t i = lag; i < r.size(); ++i) {
        const double d = std::max(1.0, r[i].second - r[i - lag].second);
        const double dphi = r[i].first - r[i - lag].first;
        sum += dphi * dphi;
        *metres += d;
    }
    return sum;
}

}  // namespace

RealityStats reality_of(const datasets::putmc::Walk& walk, const std::vector<std::optional<sim::Fix>>& fixes,
                        double floor_height_m) {
    RealityStats r;
    // Every step, as detected over the whole walk: the statistics are offline.
    const auto steps = detect_steps(walk);
    std::vector<Point> truth;
    std::vector<double> scan_t;
    for (const auto& s : walk.scans) {
        truth.push_back(datasets::putmc::to_floor(walk.truth_of(s), floor_height_m));
        scan_t.push_back(s.t_s);
    }
    for (std::size_t i = 1; i < truth.size(); ++i) r.truth_metres += distance(truth[i - 1], truth[i]);
    for (const auto& st : steps)
        if (!scan_t.empty() && st.t_s > scan_t.front() && st.t_s <= scan_t.back()) r.step_metres += st.length_m;

    // The handedness whose rotation wanders less is the compass's.
    const auto plain = rotations(steps, truth, scan_t, 1.0), mirror = rotations(steps, truth, scan_t, -1.0);
    double m_plain = 0.0, m_mirror = 0.0;
    const double ss_plain = increment_sum_sq(plain, &m_plain), ss_mirror = increment_sum_sq(mirror, &m_mirror);
    r.mirrored = ss_mirror < ss_plain;
    const auto& rot = r.mirrored ? mirror : plain;
    r.intervals = rot.size();
    r.rotation_walk_sum_sq = r.mirrored ? ss_mirror : ss_plain;
    r.rotation_walk_metres = r.mirrored ? m_mirror : m_plain;
    r.rotation_steps = rot.empty() ? 0 : rot.size() - 1;
    // Each φ also carries its own estimation error (a few steps, turns cut at a scan), which
    // inflates neighbouring increments; over 4 intervals the random walk dominates.
    r.rotation_walk4_sum_sq = increment_sum_sq(rot, &r.rotation_walk4_metres, 4);
    if (!rot.empty()) {
        const auto [lo, hi] = std::minmax_element(rot.begin(), rot.end());
        r.rotation_range_rad = hi->first - lo->first;
    }

    for (std::size_t i = 0; i < fixes.size() && i < truth.size(); ++i)
        if (fixes[i]) {
            r.fix_error.push_back({fixes[i]->at.x - truth[i].x, fixes[i]->at.y - truth[i].y});
            r.fix_truth.push_back(truth[i]);
            r.fix_t.push_back(scan_t[i]);
        }
    return r;
}

std::vector<CorrelationBin> error_correlation(const std::vector<RealityStats>& walks, const std::vector<double>& edges) {
    std::vector<CorrelationBin> bins;
    for (std::size_t b = 0; b + 1 < edges.size(); ++b) bins.push_back({edges[b], edges[b + 1], 0.0, 0});
    std::vector<double> cross(bins.size(), 0.0), norm(bins.size(), 0.0);
    for (const auto& w : walks)
        for (std::size_t i = 0; i < w.fix_error.size(); ++i)
            for (std::size_t j = i + 1; j < w.fix_error.size(); ++j) {
                const double d = distance(w.fix_truth[i], w.fix_truth[j]);
                for (std::size_t b = 0; b < bins.size(); ++b)
                    if (d >= bins[b].lo && d < bins[b].hi) {
                        const Point& a = w.fix_error[i];
                        const Point& c = w.fix_error[j];
                        cross[b] += a.x * c.x + a.y * c.y;
                        norm[b] += 0.5 * (a.x * a.x + a.y * a.y + c.x * c.x + c.y * c.y);
                        ++bins[b].pairs;
                    }
            }
    for (std::size_t b = 0; b < bins.size(); ++b) bins[b].correlation = norm[b] > 0.0 ? cross[b] / norm[b] : 0.0;
    return bins;
}

}  // namespace locus::tools::walks
