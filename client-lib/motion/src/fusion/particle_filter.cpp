#include "locus/motion/fusion/particle_filter.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "locus/motion/pdr/heading_convention.hpp"

namespace locus::fusion {

ParticleFilter::ParticleFilter(Walkable map, Point start, const ParticleConfig& config)
    : map_(std::move(map)), config_(config), rng_(config.seed) {
    if (config_.particles < 1) throw std::invalid_argument("a particle filter needs at least one particle");
    std::normal_distribution<double> n01(0.0, 1.0);
    particles_.reserve(static_cast<std::size_t>(config_.particles));
    for (int i = 0; i < config_.particles; ++i) {
        Particle p = fresh(start);
        // Spread the start only where it is walkable (a start next to a wall stays valid).
        const Point jittered{start.x + config_.initial_sigma_m * n01(rng_), start.y + config_.initial_sigma_m * n01(rng_)};
        if (map_.can_move(start, jittered)) p.at = jittered;
        particles_.push_back(p);
    }
}

Particle ParticleFilter::fresh(Point at) {
    std::normal_distribution<double> n01(0.0, 1.0);
    Particle p;
    p.at = at;
    p.bias = config_.initial_bias_sigma_rad * n01(rng_);
    p.scale = 1.0 + config_.initial_scale_sigma * n01(rng_);
    p.weight = 1.0 / config_.particles;
    return p;
}

void ParticleFilter::predict(double step_length_m, double heading_rad, bool magnetic_disturbance) {
    std::normal_distribution<double> n01(0.0, 1.0);
    const double heading_sigma =
        magnetic_disturbance ? std::max(config_.heading_sigma_rad, config_.disturbed_heading_sigma_rad)
                             : config_.heading_sigma_rad;
    for (Particle& p : particles_) {
        p.bias += config_.bias_walk_sigma_rad * n01(rng_);
        const double length = std::max(0.0, step_length_m * p.scale * (1.0 + config_.length_sigma * n01(rng_)));
        const Point to = pdr::step(p.at, length, heading_rad + p.bias + heading_sigma * n01(rng_));
        if (map_.can_move(p.at, to)) {
            p.at = to;
            continue;
        }
        // The person did walk: a wall in the way says the heading is wrong more than the
        // step is. Try other headings; a particle that needs one is less likely.
        p.weight *= config_.blocked_weight;
        for (int k = 0; k < config_.blocked_retries; ++k) {
            const double turn = config_.retry_heading_sigma_rad * n01(rng_);
            const Point alt = pdr::step(p.at, length, heading_rad + p.bias + turn);
            if (map_.can_move(p.at, alt)) {
                p.at = alt;
                p.bias += turn;
                break;
            }
        }
    }
    normalise();
    if (effective_size() < config_.resample_fraction * config_.particles) resample();
}

void ParticleFilter::update(Point fix, const Eigen::Matrix2d& r) {
    const Eigen::Matrix2d r_inv = r.inverse();
    double agreement = 0.0;  // Σ w·g: the cloud's likelihood of this fix
    for (Particle& p : particles_) {
        const Eigen::Vector2d d(fix.x - p.at.x, fix.y - p.at.y);
        const double g = std::exp(-0.5 * d.dot(r_inv * d));
        agreement += p.weight * g;
        p.weight *= config_.outlier_floor + g;
    }
    normalise();
    if (agreement < config_.injection_likelihood && config_.injection_likelihood > 0.0) {
        resample();
        inject(fix, r, config_.injection_fraction * (1.0 - agreement / config_.injection_likelihood));
    } else if (effective_size() < config_.resample_fraction * config_.particles) {
        resample();
    }
}

// Replaces a share of the (equally weighted, just resampled) particles by draws from the
// fix's Gaussian that land in a room.
void ParticleFilter::inject(Point fix, const Eigen::Matrix2d& r, double fraction) {
    const auto count = static_cast<std::size_t>(fraction * static_cast<double>(particles_.size()));
    if (count == 0) return;
    const Eigen::LLT<Eigen::Matrix2d> llt(r);
    const Eigen::Matrix2d l = llt.matrixL();
    std::normal_distribution<double> n01(0.0, 1.0);
    std::uniform_int_distribution<std::size_t> pick(0, particles_.size() - 1);
    for (std::size_t i = 0; i < count; ++i) {
        for (int attempt = 0; attempt < 20; ++attempt) {
            const Eigen::Vector2d d = l * Eigen::Vector2d(n01(rng_), n01(rng_));
            const Point at{fix.x + d.x(), fix.y + d.y()};
            if (!map_.inside(at)) continue;
            const double weight = particles_[0].weight;
            Particle p = fresh(at);
            p.weight = weight;
            particles_[pick(rng_)] = p;
            ++injected_;
            break;
        }
    }
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
