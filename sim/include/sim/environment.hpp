#pragma once
// The physical world of a scenario: RSS of each AP anywhere on the floor (mean, before the
// per-reading noise) and the magnetic field vector. Deterministic from the scenario's
// environment seed, so the survey and every walk see the same building.
#include <Eigen/Dense>
#include <random>
#include <vector>

#include "sim/scenario.hpp"

namespace locus::sim {

// A stationary Gaussian-like random field: a sum of cosines with random directions,
// wavelengths around `scale_m` and phases; standard deviation ≈ sigma.
class SmoothField {
public:
    SmoothField() = default;
    SmoothField(std::mt19937_64& rng, double sigma, double scale_m, int components = 8);
    double operator()(Point p) const;

private:
    struct Wave {
        double kx, ky, phase;
    };
    std::vector<Wave> waves_;
    double amplitude_ = 0.0;
};

class Environment {
public:
    explicit Environment(const Scenario& scenario);

    // Mean RSS (dBm) of AP i at p: log-distance path loss, walls crossed, static shadowing.
    double mean_rss(std::size_t ap, Point p) const;
    // Mean RSS (dBm) of anchor b (Scenario::beacons) at p: its true exponent, the height
    // difference, its static shadowing; no walls (the Kalman-fusion paper's area is open).
    double beacon_mean_rss(std::size_t b, Point p) const;
    // Magnetic field at p in the floor frame (x, y = local north, z up), µT.
    Eigen::Vector3d magnetic_field(Point p) const;
    // Room boundaries crossed by the straight line a→b (door openings included: the radio
    // wave goes through the wall around the door anyway for most of its path).
    int walls_between(Point a, Point b) const;

    const Scenario& scenario() const { return scenario_; }

private:
    const Scenario& scenario_;
    std::vector<SmoothField> shadowing_;
    SmoothField deflection_;
    SmoothField ripple_;
    std::vector<SmoothField> beacon_shadowing_;
};

}  // namespace locus::sim
