#include "locus/motion/fusion/walk_filter.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "cloud_moments.hpp"
#include "locus/motion/pdr/heading_convention.hpp"

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
    if (map_ && map_->floor_plan) {
        plan_ = map_->floor_plan.get();
        axis_ = plan_->axis();
    }
}

void WalkFilter::change_floor(std::optional<Walkable> map, Point shift) {
    map_ = std::move(map);
    plan_ = nullptr;
    axis_.reset();
    if (map_ && map_->floor_plan) {
        plan_ = map_->floor_plan.get();
        axis_ = plan_->axis();
    }
    if (x_.empty()) return;
    for (std::size_t i = 0; i < x_.size(); ++i) {
        x_[i] = static_cast<float>(x_[i] + shift.x);
        y_[i] = static_cast<float>(y_[i] + shift.y);
    }
    estimate_ = {estimate_.x + shift.x, estimate_.y + shift.y};
    const double sigma = std::max(spread_, config_.initial_sigma_m);
    for (std::size_t i = 0; i < x_.size(); ++i) {
        if (inside({x_[i], y_[i]})) continue;
        for (int tries = 0; tries < 20; ++tries) {
            const Point at{estimate_.x + sigma * rng_.normal(), estimate_.y + sigma * rng_.normal()};
            x_[i] = static_cast<float>(at.x);
            y_[i] = static_cast<float>(at.y);
            if (inside(at)) break;
        }
    }
    estimate();
}

bool WalkFilter::inside(Point p) const { return plan_ ? plan_->inside(p) : !map_ || map_->inside(p); }

bool WalkFilter::can_move(Point from, Point to) const { return plan_ ? plan_->can_move(from, to) : !map_ || map_->can_move(from, to); }

void WalkFilter::fresh(std::size_t i, Point around, double sigma, bool from_cloud) {
    Point at;
    for (int tries = 0; tries < 20; ++tries) {
        at = {around.x + sigma * rng_.normal(), around.y + sigma * rng_.normal()};
        if (inside(at)) break;
    }
    x_[i] = static_cast<float>(at.x);
    y_[i] = static_cast<float>(at.y);
    if (hint_ && rng_.chance(config_.hint_share)) {
        offset_[i] = static_cast<float>(pdr::wrap_angle(hint_->first + config_.hint_sigma_rad * rng_.normal()));
        mirror_[i] = static_cast<std::int8_t>(hint_->second);
    } else if (from_cloud && !hint_ && config_.cloud_share > 0.0 && rng_.chance(config_.cloud_share)) {
        const std::size_t j = static_cast<std::size_t>(rng_.below(static_cast<int>(x_.size())));
        offset_[i] = static_cast<float>(pdr::wrap_angle(offset_[j] + config_.cloud_sigma_rad * rng_.normal()));
        mirror_[i] = mirror_[j];
    } else {
        offset_[i] = static_cast<float>(rng_.uniform(-kPi, kPi));
        mirror_[i] = rng_.chance(0.5) ? 1 : -1;
    }
    scale_[i] = static_cast<float>(config_.scale_mean * std::exp(config_.scale_sigma * rng_.normal()));
    weight_[i] = 1.0f;
}

namespace {

// The nearest integer (ties to even) of |v| < 2⁵¹ as a double: adding and taking away 1.5 · 2⁵²
// rounds in the default rounding mode (IEEE arithmetic: no compiler folds it without
// -ffast-math), without the library call nearbyint costs on baseline x86-64.
double round_near(double v) {
    constexpr double kShifter = 6755399441055744.0;
    return (v + kShifter) - kShifter;
}

}  // namespace

double WalkFilter::snapped(double heading) const {
    if (!axis_) return heading;
    // Floor headings are clockwise from +y; the axis was measured as a math angle from +x.
    // Both have a 90° period here, so compare modulo π/2 (d as std::remainder gives it).
    constexpr double kQuarter = kPi / 2;
    const double axis_heading = kQuarter - *axis_;
    double d = heading - axis_heading;
    d -= kQuarter * round_near(d * (1.0 / kQuarter));
    return std::abs(d) < config_.snap_rad ? heading - d : heading;
}

namespace {

// exp(v) for the small relative random walk of the step scale (|v| ≲ 0.1): four terms of
// the series, within 1e-7 there; std::exp beyond.
double exp_small(double v) {
    if (std::abs(v) > 0.1) return std::exp(v);
    return 1.0 + v * (1.0 + v * (0.5 + v * (1.0 / 6.0 + v * (1.0 / 24.0 + v * (1.0 / 120.0)))));
}

// sin and cos of a heading: reduced to [−π/4, π/4] by quarter turns, then the Taylor series
// (to x⁹ and x¹⁰: within 2e-9 there, nanometres on a step), about four times faster than
// the library's sincos, which a step calls up to three times per particle.
void sin_cos(double a, double& s, double& c) {
    constexpr double kQuarter = kPi / 2;
    if (!(std::abs(a) < 1e6)) {  // far from any heading a step has: the library's
        s = std::sin(a), c = std::cos(a);
        return;
    }
    const double k = round_near(a * (1.0 / kQuarter));
    const double r = a - k * kQuarter, r2 = r * r;
    const double sr = r * (1.0 + r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880)))));
    const double cr = 1.0 + r2 * (-0.5 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 + r2 * (-1.0 / 3628800)))));
    switch (static_cast<long long>(k) & 3) {
        case 0: s = sr, c = cr; break;
        case 1: s = cr, c = -sr; break;
        case 2: s = -sr, c = -cr; break;
        default: s = -cr, c = sr; break;
    }
}

// φ + a small turn, wrapped to (−π, π] as pdr::wrap_angle does.
double turned(double offset, double by) {
    const double v = offset + by;
    if (v > kPi) return v - 2 * kPi > -kPi ? v - 2 * kPi : pdr::wrap_angle(v);
    if (v <= -kPi) return v + 2 * kPi <= kPi ? v + 2 * kPi : pdr::wrap_angle(v);
    return v;
}

}  // namespace

void WalkFilter::step(double length_m, double azimuth_rad) {
    if (x_.empty()) return;
    const std::size_t n = x_.size();
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double offset = turned(offset_[i], config_.offset_walk_rad * rng_.normal());
        offset_[i] = static_cast<float>(offset);
        const double scale = scale_[i] * exp_small(config_.scale_walk * rng_.normal());
        scale_[i] = static_cast<float>(scale);
        const double raw = offset + mirror_[i] * azimuth_rad;
        const double len = std::max(0.0, scale * length_m * (1.0 + config_.length_sigma * rng_.normal()));
        const Point from{x_[i], y_[i]};
        bool moved = false;
        for (int attempt = 0; attempt <= config_.blocked_retries && !moved; ++attempt) {
            const double heading = snapped(raw + config_.heading_sigma_rad * (1 + 2 * attempt) * rng_.normal());
            double sin_h, cos_h;
            sin_cos(heading, sin_h, cos_h);
            const Point to{from.x + len * sin_h, from.y + len * cos_h};
            if (can_move(from, to)) {
                x_[i] = static_cast<float>(to.x);
                y_[i] = static_cast<float>(to.y);
                moved = true;
            }
        }
        if (!moved) weight_[i] *= static_cast<float>(config_.blocked_weight);
        sum += weight_[i];
    }
    // Back to mean 1 (the estimate does not care; a long run of blocked steps cannot underflow).
    const float norm = sum > 0.0 ? static_cast<float>(static_cast<double>(n) / sum) : 0.0f;
    for (std::size_t i = 0; i < n; ++i) weight_[i] = sum > 0.0 ? weight_[i] * norm : 1.0f;
    estimate();
}

void WalkFilter::fix(Point at, const Eigen::Matrix2d& cov) {
    const int n = config_.particles;
    if (x_.empty()) {
        for (auto* v : {&x_, &y_, &offset_, &scale_, &weight_}) v->assign(static_cast<std::size_t>(n), 0.0f);
        mirror_.assign(static_cast<std::size_t>(n), 1);
        for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) fresh(i, at, config_.initial_sigma_m, false);
        estimate();
        return;
    }
    const double var = std::max(config_.fix_sigma_m * config_.fix_sigma_m, 0.5 * cov.trace());
    const float half_inv_var = static_cast<float>(0.5 / var), floor = static_cast<float>(config_.outlier_floor);
    const float ax = static_cast<float>(at.x), ay = static_cast<float>(at.y);
    double sum = 0.0, prior = 0.0, expected = 0.0;
    for (std::size_t i = 0; i < x_.size(); ++i) {
        const float dx = x_[i] - ax, dy = y_[i] - ay;
        const float like = std::exp(-(dx * dx + dy * dy) * half_inv_var);
        prior += weight_[i];
        expected += weight_[i] * like;
        weight_[i] *= floor + like;
        sum += weight_[i];
    }
    if (sum <= 0.0) std::fill(weight_.begin(), weight_.end(), 1.0f);
    resample();
    // Sensor resetting: fresh hypotheses around every fix, at the cloud's mean weight; more of
    // them the less the cloud expected this fix.
    const double surprise = prior > 0.0 ? 1.0 - expected / prior : 1.0;
    const double share = std::max(config_.reseed_fraction,
                                  config_.reseed_fraction + (config_.reseed_max_fraction - config_.reseed_fraction) * surprise);
    const int size = static_cast<int>(x_.size());
    const int k = static_cast<int>(std::min(1.0, share) * size);
    for (int i = 0; i < k; ++i) fresh(static_cast<std::size_t>(rng_.below(size)), at, std::sqrt(var), true);
    estimate();
}

namespace {

// Systematic resampling: one uniform offset u in [0, 1), n evenly spaced pointers into the
// cumulative weights (which sum to `sum`).
std::vector<std::uint32_t> systematic(const std::vector<float>& weight, double sum, std::size_t n, double u) {
    std::vector<std::uint32_t> pick(n);
    const double stride = sum / static_cast<double>(n);
    const double first = u * stride;
    double acc = 0.0;
    std::size_t i = 0;
    for (std::size_t j = 0; j < n; ++j) {
        const double target = first + static_cast<double>(j) * stride;
        while (acc + weight[i] < target && i + 1 < weight.size()) acc += weight[i++];
        pick[j] = static_cast<std::uint32_t>(i);
    }
    return pick;
}

// The KLD-sampling bound (Fox 2003, eq. 12, with the Wilson–Hilferty approximation of the χ²
// quantile): the samples that keep the KL divergence under epsilon with probability 0.99 when
// the posterior occupies k bins.
double kld_bound(std::size_t k, double epsilon) {
    if (k < 2) return 0.0;
    constexpr double kZ = 2.326;  // the standard normal's 0.99 quantile
    const double d = static_cast<double>(k - 1), a = 2.0 / (9.0 * d);
    const double c = 1.0 - a + std::sqrt(a) * kZ;
    return d / (2.0 * epsilon) * c * c * c;
}

}  // namespace

std::size_t WalkFilter::kld_size(const std::vector<std::uint32_t>& picks) const {
    // Distinct bins among the picked particles, in an open-addressed set (a pick repeats a
    // particle, and so its bin, as often as its weight says).
    std::size_t cap = 64;
    while (cap < 2 * picks.size()) cap *= 2;
    std::vector<std::uint64_t> set(cap, 0);
    const double inv_m = 1.0 / config_.kld_bin_m, inv_rad = 1.0 / config_.kld_bin_rad;
    std::size_t k = 0;
    std::uint32_t last = UINT32_MAX;
    for (const std::uint32_t i : picks) {
        if (i == last) continue;  // picks come in index order: a repeat is the same bin
        last = i;
        const auto bx = static_cast<std::int64_t>(std::floor(x_[i] * inv_m)), by = static_cast<std::int64_t>(std::floor(y_[i] * inv_m));
        const auto br = static_cast<std::int64_t>(std::floor((offset_[i] + kPi) * inv_rad));
        // 24 bits per axis (16,000 km at 1 m), 14 for the rotation, 1 for the mirror; never 0.
        const std::uint64_t key = (static_cast<std::uint64_t>(bx & 0xFFFFFF) << 40) | (static_cast<std::uint64_t>(by & 0xFFFFFF) << 16) |
                                  (static_cast<std::uint64_t>(br & 0x3FFF) << 2) | (mirror_[i] > 0 ? 2u : 0u) | 1u;
        std::size_t h = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 20) & (cap - 1);
        while (set[h] != 0 && set[h] != key) h = (h + 1) & (cap - 1);
        if (set[h] == 0) set[h] = key, ++k;
    }
    const double bound = std::ceil(kld_bound(k, config_.kld_epsilon));
    return static_cast<std::size_t>(std::clamp(bound, static_cast<double>(config_.min_particles), static_cast<double>(config_.particles)));
}

void WalkFilter::resample() {
    const std::size_t n = x_.size();
    double sum = 0.0, sum2 = 0.0;
    for (const float w : weight_) sum += w, sum2 += static_cast<double>(w) * w;
    const double n_eff = sum * sum / sum2;
    const bool degenerate = n_eff < config_.resample_fraction * static_cast<double>(n);
    const bool adaptive = config_.min_particles < config_.particles;
    const auto keep = [&] {
        const float norm = static_cast<float>(static_cast<double>(n) / sum);  // mean 1, as a re-drawn particle's
        for (float& w : weight_) w *= norm;
    };
    if (!degenerate && !adaptive) return keep();
    const double u = rng_.uniform();
    std::vector<std::uint32_t> pick = systematic(weight_, sum, n, u);
    if (adaptive) {
        // Resized only when the size needed moved by a tenth or more: each resampling costs
        // the cloud some of its diversity.
        const std::size_t target = kld_size(pick);
        const bool resize = 10 * target < 9 * n || 10 * target > 11 * n;
        if (!degenerate && !resize) return keep();
        if (resize) pick = systematic(weight_, sum, target, u);
    }
    const auto gather = [&](auto& v) {
        std::remove_reference_t<decltype(v)> next(pick.size());
        for (std::size_t j = 0; j < pick.size(); ++j) next[j] = v[pick[j]];
        v.swap(next);
    };
    gather(x_);
    gather(y_);
    gather(offset_);
    gather(scale_);
    gather(mirror_);
    weight_.assign(pick.size(), 1.0f);
}

void WalkFilter::estimate() {
    const std::size_t n = x_.size();
    constexpr float kAll = INFINITY;
    // The weighted mean, round the first particle so that the float differences stay small.
    const Point first = n ? Point{x_[0], y_[0]} : Point{};
    const CloudMoments all = cloud_moments(x_.data(), y_.data(), weight_.data(), n, first, kAll);
    if (!(all.w > 0.0)) {
        estimate_ = {};
        spread_ = 0.0;
        return;
    }
    Point at{first.x + all.x / all.w, first.y + all.y / all.w};
    // Mean shift with a flat kernel: once the particles within the radius stay the same, the
    // point does too, and the iterations left would change nothing.
    const float r2 = static_cast<float>(config_.estimate_radius_m * config_.estimate_radius_m);
    for (int it = 0; r2 > 0.0f && it < 5; ++it) {
        // Round the float centre the sums are taken from, so that a pass that changes nothing
        // leaves the point where it was.
        const Point centre{static_cast<float>(at.x), static_cast<float>(at.y)};
        const CloudMoments m = cloud_moments(x_.data(), y_.data(), weight_.data(), n, centre, r2);
        if (m.w <= 0.0) break;
        const Point shift{m.x / m.w, m.y / m.w};
        at = {centre.x + shift.x, centre.y + shift.y};
        // The next pass would start from the same float centre, and so give the same point.
        if (static_cast<float>(at.x) == static_cast<float>(centre.x) && static_cast<float>(at.y) == static_cast<float>(centre.y)) break;
    }
    estimate_ = at;
    spread_ = std::sqrt(cloud_moments(x_.data(), y_.data(), weight_.data(), n, at, kAll).d2 / all.w);
}

std::size_t WalkFilter::memory_bytes() const {
    return sizeof(*this) + (x_.capacity() + y_.capacity() + offset_.capacity() + scale_.capacity() + weight_.capacity()) * sizeof(float) +
           mirror_.capacity();
}

}  // namespace locus::fusion
