#include "locus/ranging/fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace locus::ranging {

namespace {

// The least-squares (tx_power, n) at one position and its residual sum of squares.
struct Solved {
    PathLoss model;
    double ss_res = 0.0;
    bool ok = false;
};

Solved solve_at(std::span<const Sample> samples, Point at, double dz, const FitOptions& o) {
    // rss = P + n·u with u = −10·log10(d): a line through (u, rss).
    double su = 0, sr = 0, suu = 0, sur = 0;
    const double m = static_cast<double>(samples.size());
    for (const auto& s : samples) {
        const double d = std::max(std::hypot(std::hypot(s.at.x - at.x, s.at.y - at.y), dz), kMinRange);
        const double u = -10.0 * std::log10(d);
        su += u;
        sr += s.rss;
        suu += u * u;
        sur += u * s.rss;
    }
    Solved out;
    const double var = suu - su * su / m;
    if (!(var > 1e-9)) return out;  // every sample at one distance: n is not determined
    double n = (sur - su * sr / m) / var;
    n = std::clamp(n, o.min_exponent, o.max_exponent);
    const double p = (sr - n * su) / m;  // the best P for the (clamped) n
    out.model = {p, n};
    for (const auto& s : samples) {
        const double d = std::max(std::hypot(std::hypot(s.at.x - at.x, s.at.y - at.y), dz), kMinRange);
        const double r = s.rss - rss_at(out.model, d);
        out.ss_res += r * r;
    }
    out.ok = true;
    return out;
}

ModelFit finish(std::span<const Sample> samples, Point at, const Solved& s) {
    ModelFit f;
    f.at = at;
    f.model = s.model;
    f.samples = static_cast<int>(samples.size());
    double mean = 0;
    for (const auto& x : samples) mean += x.rss;
    mean /= static_cast<double>(samples.size());
    double ss_tot = 0;
    for (const auto& x : samples) ss_tot += (x.rss - mean) * (x.rss - mean);
    f.r2 = ss_tot > 1e-12 ? 1.0 - s.ss_res / ss_tot : 0.0;
    f.residual_db = std::sqrt(s.ss_res / static_cast<double>(samples.size()));
    return f;
}

}  // namespace

std::optional<ModelFit> fit_model(std::span<const Sample> samples, Point at, double dz, const FitOptions& o) {
    if (samples.size() < 3) return std::nullopt;
    const Solved s = solve_at(samples, at, dz, o);
    if (!s.ok) return std::nullopt;
    return finish(samples, at, s);
}

std::optional<ModelFit> fit_position_and_model(std::span<const Sample> samples, const FitOptions& o) {
    if (samples.size() < 4) return std::nullopt;
    Rect area = o.area;
    if (!(area.xmax > area.xmin) || !(area.ymax > area.ymin)) {  // no area: the samples' box
        area = {samples[0].at.x, samples[0].at.y, samples[0].at.x, samples[0].at.y};
        for (const auto& s : samples) {
            area.xmin = std::min(area.xmin, s.at.x);
            area.ymin = std::min(area.ymin, s.at.y);
            area.xmax = std::max(area.xmax, s.at.x);
            area.ymax = std::max(area.ymax, s.at.y);
        }
    }
    const double w = area.xmax - area.xmin, h = area.ymax - area.ymin;
    const double step = o.grid_step > 0 ? o.grid_step : std::max(std::max(w, h) / 24.0, 0.05);
    auto cost = [&](Point p) {
        const Solved s = solve_at(samples, p, 0.0, o);
        return s.ok ? s.ss_res : std::numeric_limits<double>::infinity();
    };
    Point best{area.xmin, area.ymin};
    double best_cost = std::numeric_limits<double>::infinity();
    for (double x = area.xmin; x <= area.xmax + 1e-9; x += step)
        for (double y = area.ymin; y <= area.ymax + 1e-9; y += step) {
            const double c = cost({x, y});
            if (c < best_cost) {
                best_cost = c;
                best = {x, y};
            }
        }
    if (!std::isfinite(best_cost)) return std::nullopt;
    // Pattern search within the area, from the best grid point, down to a centimetre.
    for (double s = step / 2; s > 0.01;) {
        bool moved = false;
        for (const Point d : {Point{s, 0}, Point{-s, 0}, Point{0, s}, Point{0, -s}}) {
            const Point q{std::clamp(best.x + d.x, area.xmin, area.xmax), std::clamp(best.y + d.y, area.ymin, area.ymax)};
            const double c = cost(q);
            if (c < best_cost) {
                best_cost = c;
                best = q;
                moved = true;
            }
        }
        if (!moved) s /= 2;
    }
    return finish(samples, best, solve_at(samples, best, 0.0, o));
}

}  // namespace locus::ranging
