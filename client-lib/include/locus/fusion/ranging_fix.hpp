#pragma once
// Seed 004's fusion: a position from transmitters at known positions (trilateration or
// multilateration, locus/ranging/trilateration.hpp) is the Kalman filter's measurement, with
// the fix's own covariance as R (each axis at least floor_m², so a fix that claims
// centimetres is not taken as exact); PDR steps stay the control input (kalman.hpp).
#include <Eigen/Dense>

#include "locus/ranging/trilateration.hpp"

namespace locus::fusion {

Eigen::Matrix2d ranging_covariance(const ranging::Fix& fix, double floor_m = 0.5);

}  // namespace locus::fusion
