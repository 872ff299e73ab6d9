#include "locus/fusion/particle_filter.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "locus/pdr/heading_convention.hpp"

namespace locus::fusion {

ParticleFilter::ParticleFilter(Walkable map, Point start, const ParticleConfig& config)
    : map_(std::move(map)), config_(config), rng_(config.seed) {
    if (config_.particles < 1) throw std::invalid_argument("a particle filter needs at least one particle");
    std::normal_distribution<double> n01(0.0, 1.0);
    const double w = 1.0 / config_.particles;
    particles_.reserve(static_cast<std::size_t>(config_.particles));
    for (int i = 0; i < config_.particles; ++i) {
        Particle p;
        p.at = start;
        // Spread the start only where it is walkable (a start next to a wall stays valid).
        const Point jittered{start.x + config_.initial_sigma_m * n01(rng_), start.y + config_.initial_sigma_m * n01(rng_)};
        if (map_.can_move(start, jittered)) p.at = jittered;
        p.bias = config_.initial_bias_sigma_rad * n01(rng_);
        p.scale = 1.0 + config_.initial_scale_sigma * n01(rng_);
        p.weight = w;
        particles_.push_back(p);
    }
}

void ParticleFilter::predict(double step_length_m, double heading_rad) {
    std::normal_distribution<double> n01(0.0, 1.0);
    for (Particle& p : particles_) {
        p.bias += config_.bias_walk_sigma_rad * n01(rng_);
        const double heading = heading_rad + p.bias + config_.heading_sigma_rad * n01(rng_);
        const double length = step_length_m * p.scale * (1.0 + config_.length_sigma * n01(rng_));
        const Point to = pdr::step(p.at, std::max(0.0, length), heading);
        if (map_.can_move(p.at, to))
            p.at = to;
        else
            p.weight *= config_.blocked_weight;
    }
    normalise();
    if (effective_size() < config_.resample_fraction * config_.particles) resample();
}

void ParticleFilter::update(Point fix, const Eigen::Matrix2d& r) {
    const Eigen::Matrix2d r_inv = r.inverse();
    for (Particle& p : particles_) {
        const Eigen::Vector2d d(fix.x - p.at.x, fix.y - p.at.y);
        p.weight *= config_.outlier_floor + std::exp(-0.5 * d.dot(r_inv * d));
    }
    normalise();
    if (effective_size() < config_.resample_fraction * config_.particles) resample();
}

Point ParticleFilter::position() const {
    Point m;
    for (const Particle& p : particles_) {
        m.x += p.weight * p.at.x;
        m.y += p.weight * p.at.y;
    }
    return m;
}

double ParticleFilter::effective_size() const {
    double s = 0.0;
    for (const Particle& p : particles_) s += p.weight * p.weight;
    return s > 0.0 ? 1.0 / s : 0.0;
}

void ParticleFilter::normalise() {
    double total = 0.0;
    for (const Particle& p : particles_) total += p.weight;
    // Every weight underflowed (all particles blocked many times): start afresh, uniform.
    const double n = static_cast<double>(particles_.size());
    for (Particle& p : particles_) p.weight = total > 0.0 ? p.weight / total : 1.0 / n;
}

// Systematic resampling: one uniform draw, N evenly spaced pointers, low variance.
void ParticleFilter::resample() {
    const std::size_t n = particles_.size();
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::normal_distribution<double> n01(0.0, 1.0);
    std::vector<Particle> next;
    next.reserve(n);
    const double step = 1.0 / static_cast<double>(n);
    double pointer = u01(rng_) * step;
    double cumulative = particles_[0].weight;
    std::size_t i = 0;
    for (std::size_t k = 0; k < n; ++k) {
        while (pointer > cumulative && i + 1 < n) cumulative += particles_[++i].weight;
        Particle p = particles_[i];
        p.weight = step;
        const Point jittered{p.at.x + config_.roughening_m * n01(rng_), p.at.y + config_.roughening_m * n01(rng_)};
        if (map_.can_move(p.at, jittered)) p.at = jittered;
        next.push_back(p);
        pointer += step;
    }
    particles_ = std::move(next);
}

}  // namespace locus::fusion
