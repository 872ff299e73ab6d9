#include "locus/fusion/walk_filter.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "locus/pdr/heading_convention.hpp"

namespace locus::fusion {

namespace {
constexpr double kPi = std::numbers::pi;
}

std::optional<double> corridor_axis(const locus::plan::Plan& plan) {
    constexpr int kBins = 90;  // 1° bins over [0°, 90°)
    std::vector<double> hist(kBins, 0.0);
    double total = 0.0;
    for (const auto& w : plan.walls)
        for (std::size_t i = 1; i < w.line.size(); ++i) {
            const double dx = w.line[i].x - w.line[i - 1].x, dy = w.line[i].y - w.line[i - 1].y;
            const double len = std::hypot(dx, dy);
            if (len <= 0.0) continue;
            double a = std::fmod(std::atan2(dy, dx), kPi / 2);
            if (a < 0) a += kPi / 2;
            hist[static_cast<int>(a / (kPi / 2) * kBins) % kBins] += len;
            total += len;
        }
    if (total <= 0.0) return std::nullopt;
    // The best ±2° window, circular over the 90° period.
    int best = 0;
    double best_sum = -1.0;
    for (int b = 0; b < kBins; ++b) {
        double s = 0.0;
        for (int d = -2; d <= 2; ++d) s += hist[(b + d + kBins) % kBins];
        if (s > best_sum) best_sum = s, best = b;
    }
    if (best_sum < 0.3 * total) return std::nullopt;  // no axis holds a good share of the walls
    // The window's length-weighted mean bin (offsets from `best`, so the 90° wrap is harmless).
    double shift = 0.0;
    for (int d = -2; d <= 2; ++d) shift += d * hist[(best + d + kBins) % kBins];
    double axis = (best + 0.5 + shift / best_sum) * (kPi / 2) / kBins;
    if (axis < 0) axis += kPi / 2;
    if (axis >= kPi / 2) axis -= kPi / 2;
    return axis;
}

WalkFilter::WalkFilter(std::optional<Walkable> map, const WalkFilterConfig& config)
    : map_(std::move(map)), config_(config), rng_(config.seed) {
    if (map_ && map_->floor_plan) axis_ = corridor_axis(map_->floor_plan->plan());
}

WalkFilter::P WalkFilter::fresh(Point around, double sigma) {
    std::normal_distribution<double> n(0.0, 1.0);
    std::uniform_real_distribution<double> u(-kPi, kPi);
    P p;
    for (int tries = 0; tries < 20; ++tries) {
        p.at = {around.x + sigma * n(rng_), around.y + sigma * n(rng_)};
        if (!map_ || map_->inside(p.at)) break;
    }
    if (hint_ && std::bernoulli_distribution(config_.hint_share)(rng_)) {
        p.offset = pdr::wrap_angle(hint_->first + config_.hint_sigma_rad * n(rng_));
        p.mirror = hint_->second;
    } else {
        p.offset = u(rng_);
        p.mirror = std::bernoulli_distribution(0.5)(rng_) ? 1.0 : -1.0;
    }
    p.scale = config_.scale_mean * std::exp(config_.scale_sigma * n(rng_));
    p.weight = 1.0;
    return p;
}

double WalkFilter::snapped(double heading) const {
    if (!axis_) return heading;
    // Floor headings are clockwise from +y; the axis was measured as a math angle from +x.
    // Both have a 90° period here, so compare modulo π/2.
    const double axis_heading = kPi / 2 - *axis_;
    double d = std::remainder(heading - axis_heading, kPi / 2);
    return std::abs(d) < config_.snap_rad ? heading - d : heading;
}

void WalkFilter::step(double length_m, double azimuth_rad) {
    if (particles_.empty()) return;
    std::normal_distribution<double> n(0.0, 1.0);
    for (P& p : particles_) {
        p.offset = pdr::wrap_angle(p.offset + config_.offset_walk_rad * n(rng_));
        p.scale *= std::exp(config_.scale_walk * n(rng_));
        const double raw = p.offset + p.mirror * azimuth_rad;
        const double len = std::max(0.0, p.scale * length_m * (1.0 + config_.length_sigma * n(rng_)));
        bool moved = false;
        for (int attempt = 0; attempt <= config_.blocked_retries && !moved; ++attempt) {
            const double heading = snapped(raw + config_.heading_sigma_rad * (1 + 2 * attempt) * n(rng_));
            const Point to = pdr::step(p.at, len, heading);
            if (!map_ || map_->can_move(p.at, to)) {
                p.at = to;
                moved = true;
            }
        }
        if (!moved) p.weight *= config_.blocked_weight;
    }
    double sum = 0.0;
    for (const P& p : particles_) sum += p.weight;
    if (sum <= 0.0)
        for (P& p : particles_) p.weight = 1.0;
}

void WalkFilter::fix(Point at, const Eigen::Matrix2d& cov) {
    const int n = config_.particles;
    if (particles_.empty()) {
        particles_.reserve(n);
        for (int i = 0; i < n; ++i) particles_.push_back(fresh(at, config_.initial_sigma_m));
        return;
    }
    const double var = std::max(config_.fix_sigma_m * config_.fix_sigma_m, 0.5 * cov.trace());
    double sum = 0.0, prior = 0.0, expected = 0.0;
    for (P& p : particles_) {
        const double d2 = (p.at.x - at.x) * (p.at.x - at.x) + (p.at.y - at.y) * (p.at.y - at.y);
        const double like = std::exp(-0.5 * d2 / var);
        prior += p.weight;
        expected += p.weight * like;
        p.weight *= config_.outlier_floor + like;
        sum += p.weight;
    }
    if (sum <= 0.0)
        for (P& p : particles_) p.weight = 1.0;
    resample();
    // Sensor resetting: fresh hypotheses around every fix, at the cloud's mean weight; more of
    // them the less the cloud expected this fix.
    const double surprise = prior > 0.0 ? 1.0 - expected / prior : 1.0;
    const double share = std::max(config_.reseed_fraction,
                                  config_.reseed_fraction + (config_.reseed_max_fraction - config_.reseed_fraction) * surprise);
    const int k = static_cast<int>(std::min(1.0, share) * n);
    std::uniform_int_distribution<int> pick(0, n - 1);
    for (int i = 0; i < k; ++i) particles_[pick(rng_)] = fresh(at, std::sqrt(var));
}

void WalkFilter::resample() {
    double sum = 0.0, sum2 = 0.0;
    for (const P& p : particles_) sum += p.weight, sum2 += p.weight * p.weight;
    const double n_eff = sum * sum / sum2;
    if (n_eff >= config_.resample_fraction * particles_.size()) {
        for (P& p : particles_) p.weight *= particles_.size() / sum;  // mean 1, as a re-drawn particle's
        return;
    }
    // Systematic resampling.
    std::vector<P> next;
    next.reserve(particles_.size());
    const double stride = sum / particles_.size();
    double u = std::uniform_real_distribution<double>(0.0, stride)(rng_), acc = 0.0;
    std::size_t i = 0;
    for (std::size_t j = 0; j < particles_.size(); ++j) {
        const double target = u + j * stride;
        while (acc + particles_[i].weight < target && i + 1 < particles_.size()) acc += particles_[i++].weight;
        next.push_back(particles_[i]);
        next.back().weight = 1.0;
    }
    particles_ = std::move(next);
}

Point WalkFilter::position() const {
    double x = 0.0, y = 0.0, w = 0.0;
    for (const P& p : particles_) x += p.weight * p.at.x, y += p.weight * p.at.y, w += p.weight;
    if (w <= 0.0) return {};
    Point at{x / w, y / w};
    const double r2 = config_.estimate_radius_m * config_.estimate_radius_m;
    for (int it = 0; r2 > 0.0 && it < 5; ++it) {
        double sx = 0.0, sy = 0.0, sw = 0.0;
        for (const P& p : particles_) {
            const double dx = p.at.x - at.x, dy = p.at.y - at.y;
            if (dx * dx + dy * dy <= r2) sx += p.weight * p.at.x, sy += p.weight * p.at.y, sw += p.weight;
        }
        if (sw <= 0.0) break;
        at = {sx / sw, sy / sw};
    }
    return at;
}

double WalkFilter::spread() const {
    const Point at = position();
    double sum = 0.0, w = 0.0;
    for (const P& p : particles_) {
        sum += p.weight * ((p.at.x - at.x) * (p.at.x - at.x) + (p.at.y - at.y) * (p.at.y - at.y));
        w += p.weight;
    }
    return w > 0.0 ? std::sqrt(sum / w) : 0.0;
}

}  // namespace locus::fusion
