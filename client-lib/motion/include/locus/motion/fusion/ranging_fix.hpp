#pragma once
// The fusion of the Kalman-fusion paper (docs/spec.md §8 "Sources"): a position from transmitters
// at known positions (trilateration or multilateration, locus/ranging/trilateration.hpp) is the
// Kalman filter's measurement and PDR steps its control input (kalman.hpp: one filter for WiFi
// fixes and ranging fixes alike). What differs is where R comes from:
//  - the paper (its §3.3, equations 6–10): R and Q are constants it tunes by hand, so R is
//    configured (a fixed σ per axis) and Q a fixed σ per step (trilateration_kalman_config());
//  - ours: R is the fix's own covariance (each axis at least floor_m², so a fix that claims
//    centimetres is not taken as exact), Q grows with the distance walked.
#include <Eigen/Dense>

#include "locus/motion/fusion/kalman.hpp"
#include "locus/ranging/trilateration.hpp"

namespace locus::fusion {

Eigen::Matrix2d ranging_covariance(const ranging::Fix& fix, double floor_m = 0.5);

struct RangingKalmanConfig {
    KalmanConfig kalman;          // Q (step_sigma_floor_m per step + step_sigma_per_m per metre)
    double fixed_r_sigma_m = 0.0; // > 0: R = σ² I whatever the fix says (the Kalman-fusion paper); 0: the fix's covariance
    double r_floor_m = 0.5;       // with the fix's covariance: each axis at least this σ
    double r_scale = 1.0;         // with the fix's covariance: × this (its spread is a model's, not a truth)
};

// R for one ranging fix under `config`.
Eigen::Matrix2d ranging_measurement_noise(const ranging::Fix& fix, const RangingKalmanConfig& config);

// The Kalman-fusion paper's filter as the paper states it: Q constant per PDR step, R a configured
// constant. The paper gives no values; these were tuned on `locus sim --scenario open_area` walks
// with seeds 101..160 (docs/transmitters.md), never on the reported ones.
RangingKalmanConfig trilateration_kalman_config();

// Ours (multilateration fixes with their covariance as R, Q growing with the distance walked),
// tuned on `locus sim --scenario open_area` walks with seeds 101..160 (docs/transmitters.md):
// what `locus sim`, `locus replay` and the server's kalman_ranging tracks run.
RangingKalmanConfig ranging_kalman_config();

}  // namespace locus::fusion
