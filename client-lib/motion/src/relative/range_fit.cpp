#include "locus/motion/relative/range_fit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace locus::relative {

namespace {

constexpr double kMinD = 0.1;  // m: keeps ln d and the Jacobian finite at a measured position

double cost(std::span<const Point> at, std::span<const double> distance, Point b) {
    double c = 0;
    for (std::size_t i = 0; i < at.size(); ++i) {
        const double r = std::log(std::max(kMinD, std::hypot(at[i].x - b.x, at[i].y - b.y))) - std::log(std::max(kMinD, distance[i]));
        c += r * r;
    }
    return c;
}

Point gauss_newton(std::span<const Point> at, std::span<const double> distance, Point b) {
    double lambda = 1e-3;  // Levenberg damping, raised whenever a step makes things worse
    double c = cost(at, distance, b);
    for (int iter = 0; iter < 20; ++iter) {
        double a11 = 0, a12 = 0, a22 = 0, g1 = 0, g2 = 0;
        for (std::size_t i = 0; i < at.size(); ++i) {
            const double dx = b.x - at[i].x, dy = b.y - at[i].y;
            const double d2 = std::max(kMinD * kMinD, dx * dx + dy * dy);
            const double r = 0.5 * std::log(d2) - std::log(std::max(kMinD, distance[i]));
            const double jx = dx / d2, jy = dy / d2;  // ∂ ln|b − a_i| / ∂b
            a11 += jx * jx, a12 += jx * jy, a22 += jy * jy;
            g1 += jx * r, g2 += jy * r;
        }
        const double m11 = a11 * (1 + lambda), m22 = a22 * (1 + lambda);
        const double det = m11 * m22 - a12 * a12;
        if (!(std::abs(det) > 1e-18)) break;
        const Point next{b.x - (m22 * g1 - a12 * g2) / det, b.y - (m11 * g2 - a12 * g1) / det};
        const double cn = cost(at, distance, next);
        if (cn < c) {
            const bool converged = c - cn < 1e-9;
            b = next, c = cn, lambda = std::max(1e-6, lambda / 3);
            if (converged) break;
        } else {
            lambda *= 10;
        }
    }
    return b;
}

}  // namespace

std::optional<Point> fit_target(std::span<const Point> at, std::span<const double> distance, Point around, double radius,
                                double prefer_deg) {
    if (at.size() < 3 || at.size() != distance.size()) return std::nullopt;
    constexpr int kStarts = 8;
    std::optional<Point> best;
    double best_cost = 0, best_turn = 0;
    for (int s = 0; s < kStarts; ++s) {
        const double a = 2 * std::numbers::pi * s / kStarts;
        const Point b = gauss_newton(at, distance, {around.x + radius * std::cos(a), around.y + radius * std::sin(a)});
        const double c = cost(at, distance, b);
        double turn = std::atan2(b.y - around.y, b.x - around.x) * 180 / std::numbers::pi - prefer_deg;
        turn = std::abs(std::remainder(turn, 360.0));
        // Fits within 1 % of each other are alike (the two mirror images of a straight walk).
        const bool better = !best || c < best_cost * 0.99 || (c <= best_cost * 1.01 && turn < best_turn);
        if (better) best = b, best_cost = c, best_turn = turn;
    }
    return best;
}

}  // namespace locus::relative
