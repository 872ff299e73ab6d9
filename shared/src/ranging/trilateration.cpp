#include "locus/ranging/trilateration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace locus::ranging {

Ellipse ellipse_of(double sxx, double syy, double sxy) {
    const double mean = 0.5 * (sxx + syy);
    const double half = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
    Ellipse e;
    e.semi_major = std::sqrt(std::max(0.0, mean + half));
    e.semi_minor = std::sqrt(std::max(0.0, mean - half));
    e.angle_deg = 0.5 * std::atan2(2.0 * sxy, sxx - syy) * 180.0 / std::numbers::pi;
    return e;
}

namespace {

struct Ranged {
    Point at;
    double d = 0.0;
};

// The point whose distances to a, b and c are da, db and dc, from the two linear equations
// left after subtracting a's circle from b's and c's; nullopt when the three are (nearly) in a line.
std::optional<Point> solve_triple(const Ranged& a, const Ranged& b, const Ranged& c) {
    const double a11 = 2.0 * (b.at.x - a.at.x), a12 = 2.0 * (b.at.y - a.at.y);
    const double a21 = 2.0 * (c.at.x - a.at.x), a22 = 2.0 * (c.at.y - a.at.y);
    const double na = a.at.x * a.at.x + a.at.y * a.at.y;
    const double r1 = a.d * a.d - b.d * b.d + b.at.x * b.at.x + b.at.y * b.at.y - na;
    const double r2 = a.d * a.d - c.d * c.d + c.at.x * c.at.x + c.at.y * c.at.y - na;
    const double det = a11 * a22 - a12 * a21;
    // Relative to the triangle's size: twice its area against the square of its longest side.
    const double scale = std::max({a11 * a11 + a12 * a12, a21 * a21 + a22 * a22, 1e-12});
    if (std::fabs(det) < 1e-6 * scale) return std::nullopt;
    return Point{(r1 * a22 - a12 * r2) / det, (a11 * r2 - r1 * a21) / det};
}

}  // namespace

std::optional<Fix> trilaterate(std::span<const Heard> heard, const TrilaterationOptions& o) {
    std::vector<std::pair<double, Ranged>> by_rss;  // strongest first
    by_rss.reserve(heard.size());
    for (const auto& h : heard) {
        const double d = horizontal(range_of(h.tx.model, h.rss), h.tx.dz);
        if (d <= o.cutoff) by_rss.push_back({h.rss, Ranged{h.tx.at, d}});
    }
    std::stable_sort(by_rss.begin(), by_rss.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    if (by_rss.size() > static_cast<std::size_t>(std::max(o.max_transmitters, 3))) by_rss.resize(std::max(o.max_transmitters, 3));
    const std::size_t m = by_rss.size();
    if (m < 3) return std::nullopt;
    std::vector<Ranged> r(m);
    for (std::size_t i = 0; i < m; ++i) r[i] = by_rss[i].second;

    // Votes against each transmitter's range (the Kalman-fusion paper, equation 4); the fewest is
    // the reference.
    std::size_t ref = 0;
    int fewest = -1;
    for (std::size_t n = 0; n < m; ++n) {
        int votes = 0;
        for (std::size_t l = 0; l < m; ++l)
            if (l != n && distance(r[n].at, r[l].at) - r[n].d > o.vote_slack * r[l].d) ++votes;
        if (fewest < 0 || votes < fewest) {
            fewest = votes;
            ref = n;
        }
    }
    // Equation 5: with the reference's range trusted, another transmitter's range lies within
    // the triangle inequality's interval [|D − d_ref|, D + d_ref], D their separation.
    if (o.correct)
        for (std::size_t l = 0; l < m; ++l) {
            if (l == ref) continue;
            const double sep = distance(r[ref].at, r[l].at);
            r[l].d = std::clamp(r[l].d, std::fabs(sep - r[ref].d), sep + r[ref].d);
        }

    std::vector<Point> solutions;
    for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = i + 1; j < m; ++j)
            for (std::size_t k = j + 1; k < m; ++k)
                if (auto p = solve_triple(r[i], r[j], r[k])) solutions.push_back(*p);
    if (solutions.empty()) return std::nullopt;
    Fix fix;
    for (const auto& p : solutions) {
        fix.at.x += p.x;
        fix.at.y += p.y;
    }
    const double count = static_cast<double>(solutions.size());
    fix.at.x /= count;
    fix.at.y /= count;
    double sxx = 0, syy = 0, sxy = 0;
    for (const auto& p : solutions) {
        sxx += (p.x - fix.at.x) * (p.x - fix.at.x);
        syy += (p.y - fix.at.y) * (p.y - fix.at.y);
        sxy += (p.x - fix.at.x) * (p.y - fix.at.y);
    }
    // The triples' spread: the answer is their mean, so its own spread is σ²/count.
    fix.sxx = sxx / count / count;
    fix.syy = syy / count / count;
    fix.sxy = sxy / count / count;
    fix.uncertainty = ellipse_of(fix.sxx, fix.syy, fix.sxy);
    fix.rms_residual = std::sqrt((sxx + syy) / count);
    fix.used = static_cast<int>(m);
    return fix;
}

namespace {

struct Normal {
    Eigen::Matrix2d h = Eigen::Matrix2d::Zero();  // JᵀWJ
    Eigen::Vector2d g = Eigen::Vector2d::Zero();  // JᵀWr
    double cost = 0;                              // Σ robust loss
    double weighted_sq = 0;                       // Σ w r²
};

// The residuals r = rss − model(p) and their Jacobian at p, weighted for the Cauchy loss
// ρ(r) = k²/2·ln(1 + (r/k)²): its weight 1/(1 + (r/k)²) all but ignores a glitched reading.
Normal normal_at(std::span<const Heard> heard, Point p, double k) {
    Normal n;
    for (const auto& h : heard) {
        const double dx = p.x - h.tx.at.x, dy = p.y - h.tx.at.y;
        const double s2 = std::max(dx * dx + dy * dy + h.tx.dz * h.tx.dz, kMinRange * kMinRange);
        const double r = h.rss - rss_at(h.tx.model, std::sqrt(s2));
        const double u = r / k;
        const double w = 1.0 / (1.0 + u * u);
        n.cost += 0.5 * k * k * std::log1p(u * u);
        n.weighted_sq += w * r * r;
        // ∂r/∂p = 10·n/ln10 · (p − a)/s²
        const double c = 10.0 * h.tx.model.exponent / std::numbers::ln10 / s2;
        const Eigen::Vector2d j(c * dx, c * dy);
        n.h.noalias() += w * j * j.transpose();
        n.g += (w * r) * j;
    }
    return n;
}

double cost_at(std::span<const Heard> heard, Point p, double k) {
    double cost = 0;
    for (const auto& h : heard) {
        const double dx = p.x - h.tx.at.x, dy = p.y - h.tx.at.y;
        const double u = (h.rss - rss_at(h.tx.model, std::sqrt(dx * dx + dy * dy + h.tx.dz * h.tx.dz))) / k;
        cost += 0.5 * k * k * std::log1p(u * u);
    }
    return cost;
}

struct Refined {
    Point at;
    double cost = 0;
    int iterations = 0;
};

// Levenberg–Marquardt from `p`: the Gauss–Newton step of the reweighted problem, damped
// until the robust cost falls.
Refined refine(std::span<const Heard> heard, Point p, double k, const MultilaterationOptions& o) {
    Refined out{p, cost_at(heard, p, k), 0};
    double lambda = 1e-3;
    for (int it = 0; it < o.max_iterations; ++it) {
        out.iterations = it + 1;
        const Normal n = normal_at(heard, out.at, k);
        bool stepped = false;
        double step = 0;
        for (int tries = 0; tries < 10 && !stepped; ++tries) {
            // Marquardt's damping scales the diagonal: (JᵀWJ + λ diag(JᵀWJ)) δ = −JᵀW r.
            Eigen::Matrix2d a = n.h;
            a.diagonal() = a.diagonal() * (1.0 + lambda) + Eigen::Vector2d::Constant(1e-12);
            if (!(std::fabs(a.determinant()) > 0)) break;
            // A fixed 2×2 inverse is Eigen's closed form: no factorisation cost per try.
            const Eigen::Vector2d delta = -(a.inverse() * n.g);
            const double dx = delta.x(), dy = delta.y();
            const Point q{out.at.x + dx, out.at.y + dy};
            const double c = cost_at(heard, q, k);
            if (std::isfinite(c) && c <= out.cost) {
                out.at = q;
                out.cost = c;
                step = std::hypot(dx, dy);
                lambda = std::max(lambda / 10.0, 1e-9);
                stepped = true;
            } else {
                lambda *= 10.0;
            }
        }
        if (!stepped || step < o.tolerance) break;
    }
    return out;
}

}  // namespace

std::optional<Fix> multilaterate(std::span<const Heard> heard, const MultilaterationOptions& o) {
    if (heard.size() < 3) return std::nullopt;
    const double k = o.loss_scale * o.sigma_db;
    // Two starts, the cheaper answer kept: the centroid weighted by 1/range² (near the truth
    // when every reading is sound) and, when that fit leaves a reading far out, the plain
    // centroid (which one glitched, far too strong reading cannot drag onto its transmitter,
    // where the robust cost has a local minimum).
    Point weighted, plain;
    double wsum = 0, heaviest = 0;
    for (const auto& h : heard) {
        const double d = std::max(range_of(h.tx.model, h.rss), kMinRange);
        const double w = 1.0 / (d * d);
        heaviest = std::max(heaviest, w);
        weighted.x += w * h.tx.at.x;
        weighted.y += w * h.tx.at.y;
        wsum += w;
        plain.x += h.tx.at.x;
        plain.y += h.tx.at.y;
    }
    weighted.x /= wsum;
    weighted.y /= wsum;
    plain.x /= static_cast<double>(heard.size());
    plain.y /= static_cast<double>(heard.size());
    Refined best = refine(heard, weighted, k, o);
    // The other start is tried only when one reading outweighs all others in the weighted one,
    // or the fit leaves a reading far out (past 3 loss scales: 18 dB at the defaults, a 4.5σ
    // event for honest shadowing): it doubled the time of every query.
    bool doubtful = heaviest > 0.5 * wsum;  // one reading made the weighted start
    for (const auto& h : heard) {
        const double d = std::hypot(std::hypot(best.at.x - h.tx.at.x, best.at.y - h.tx.at.y), h.tx.dz);
        doubtful = doubtful || std::fabs(h.rss - rss_at(h.tx.model, d)) > 3.0 * k;
    }
    if (doubtful) {
        const Refined other = refine(heard, plain, k, o);
        if (other.cost < best.cost) best = other;
    }
    const Point p = best.at;
    Fix fix;
    fix.iterations = best.iterations;
    const Normal n = normal_at(heard, p, k);
    const double m = static_cast<double>(heard.size());
    // The scatter the residuals show, never below the shadowing assumed.
    const double s2 = std::max(o.sigma_db * o.sigma_db, n.weighted_sq / std::max(m - 2.0, 1.0));
    if (n.h.determinant() > 1e-12) {
        const Eigen::Matrix2d cov = s2 * n.h.inverse();
        fix.sxx = cov(0, 0);
        fix.syy = cov(1, 1);
        fix.sxy = cov(0, 1);
        fix.uncertainty = ellipse_of(fix.sxx, fix.syy, fix.sxy);
    } else {
        const double inf = std::numeric_limits<double>::infinity();
        fix.sxx = fix.syy = inf;
        fix.uncertainty = {inf, inf, 0.0};
    }
    fix.at = p;
    fix.used = static_cast<int>(heard.size());
    fix.rms_residual = std::sqrt(n.weighted_sq / m);
    return fix;
}

}  // namespace locus::ranging
