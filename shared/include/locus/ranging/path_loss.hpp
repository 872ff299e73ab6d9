#pragma once
// The log-distance path-loss model of a transmitter at a known position (seeds 002, 004):
//   rss(d) = tx_power − 10·n·log10(d / 1 m)
// with tx_power the RSS at 1 m and n the path-loss exponent, and its inverse, ranging.
#include <optional>

#include "locus/geometry.hpp"

namespace locus::ranging {

// Below this a modelled distance is taken as this: the model has no meaning inside 1 m's
// near field, and log10(0) none at all.
inline constexpr double kMinRange = 0.1;

struct PathLoss {
    double tx_power = -40.0;  // dBm at 1 m
    double exponent = 2.0;    // n
};

struct Transmitter {
    Point at;
    // Height above the phone (m); the horizontal distance is what trilateration solves for.
    double dz = 0.0;
    PathLoss model;
};

// The RSS the model predicts at distance `d` (m, clamped to kMinRange).
double rss_at(const PathLoss& m, double d);
// The distance at which the model predicts `rss` (the Kalman-fusion paper's equation 2, d0 = 1 m).
double range_of(const PathLoss& m, double rss);
// The horizontal distance for a slant range and a height difference (0 when the slant is
// shorter than the height).
double horizontal(double slant, double dz);

}  // namespace locus::ranging
