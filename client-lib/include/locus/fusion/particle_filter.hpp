#pragma once
// Particle filter over the floor plan (SPEC §6 "beyond the seeds", after seed 002's grid
// Bayes filter). Each particle carries a position, a heading bias and a step-length scale:
// the compass error in a magnetically disturbed area is slow and shared by many steps, so
// it is a state to estimate, not white noise. A PDR step moves every particle with its own
// bias and noise; a move that would cross a wall or leave the rooms is not made (the
// particle stays and is down-weighted). A WiFi fix reweights with a Gaussian of the fix
// covariance plus a small uniform floor, so one wild fix cannot wipe out the cloud.
#include <Eigen/Dense>
#include <cstdint>
#include <random>
#include <vector>

#include "locus/fusion/walkable.hpp"

namespace locus::fusion {

struct ParticleConfig {
    int particles = 1000;
    std::uint64_t seed = 1;
    double initial_sigma_m = 0.5;
    double initial_bias_sigma_rad = 0.35;
    double initial_scale_sigma = 0.08;     // relative step-length scale error
    double heading_sigma_rad = 0.08;       // per-step heading noise
    double bias_walk_sigma_rad = 0.04;     // per-step random walk of the heading bias
    double length_sigma = 0.08;            // per-step relative length noise
    double blocked_weight = 0.05;          // weight factor of a particle whose move was blocked
    double outlier_floor = 0.02;           // uniform part of the fix likelihood
    double resample_fraction = 0.5;        // resample when N_eff < this · N
    double roughening_m = 0.1;             // jitter after resampling (kept only if legal)
};

struct Particle {
    Point at;
    double bias = 0.0;   // added to the PDR heading, rad
    double scale = 1.0;  // multiplies the PDR step length
    double weight = 0.0;
};

class ParticleFilter {
public:
    ParticleFilter(Walkable map, Point start, const ParticleConfig& config = {});

    void predict(double step_length_m, double heading_rad);
    void update(Point fix, const Eigen::Matrix2d& r);

    Point position() const;  // weighted mean
    const std::vector<Particle>& particles() const { return particles_; }
    double effective_size() const;
    const Walkable& map() const { return map_; }

private:
    void normalise();
    void resample();

    Walkable map_;
    ParticleConfig config_;
    std::mt19937_64 rng_;
    std::vector<Particle> particles_;
};

}  // namespace locus::fusion
