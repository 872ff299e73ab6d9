#pragma once
// Bonjorn López 2016's heuristic relative-direction estimator (its section 4.1). Phone A walks (its PDR
// gives positions in a local east/north plane), phone B stays put, and every step comes with a
// distance A–B (from RSSI, or acoustic ranging when close). Each walked direction, seen from a
// reference position, gets a weight
//   w_k = (d_0 − d_k) / Δρ                                   (Bonjorn López 2016 eq. 4.1)
// (1: walking straight at B; −1: straight away). Directions with |w| ≥ 0.5 become measurements
// of B's direction for a 1-D angle Kalman filter, repeated 1–5 times by weight stage; negative
// weights count the opposite direction. The reference moves to A when w > 15 (NLOS → LOS) or
// when the distance has shrunk to a fifth of the reference one, and the filter restarts then.
// B's position is where the line from the reference along the estimate meets the circle of
// radius d_k around A (the farther point: A has not passed B yet).
#include <optional>

#include "locus/geometry.hpp"
#include "locus/motion/relative/angle_kalman.hpp"

namespace locus::relative {

struct DirectionParams {
    double min_weight = 0.5;   // below: the direction says nothing
    double max_weight = 15.0;  // above: the reference distance was NLOS, restart there
    double shrink_reset = 0.2; // restart when d_k ≤ this × d_0
    // Δρ below which no weight is formed: the thesis divides by Δρ, and a PDR position a few
    // centimetres from the reference would make any distance noise a huge weight.
    double min_rho = 0.5;
    AngleKalmanParams kalman;
};

// How many times a direction with weight |w| counts (seed: 0.5–0.8 once, 0.8–1.5 twice,
// 1.5–4 three, 4–9 four, 9–15 five times); 0 outside [0.5, 15].
int weight_repeats(double abs_weight);

// What one step did, for tests and plots.
enum class StepOutcome { Reference, TooClose, Discarded, Measured, ResetLos, ResetShrunk };

class DirectionEstimator {
public:
    explicit DirectionEstimator(DirectionParams p = {}) : params_(p), kalman_(p.kalman) {}

    // A's position (m, x east, y north) and the A–B distance measured there (m).
    StepOutcome step(Point a, double distance);

    // The estimated direction of B seen from the reference, degrees counter-clockwise from
    // east; the last one before a restart until the restarted filter has one.
    std::optional<double> direction_deg() const;
    // B's estimated position (circle–line intersection; the reference plus d_0 along the
    // direction, Bonjorn López 2016 eq. 4.11, when the circle does not reach the line).
    std::optional<Point> target() const;
    Point reference() const { return ref_; }
    double reference_distance() const { return d0_; }
    double last_weight() const { return last_weight_; }

private:
    void restart(Point a, double distance);

    DirectionParams params_;
    AngleKalman kalman_;
    bool started_ = false;
    Point ref_;
    double d0_ = 0.0;
    Point a_;
    double dk_ = 0.0;
    double last_weight_ = 0.0;
    std::optional<double> held_;  // direction kept over a restart
};

// The intersection of the ray from `origin` at `angle_deg` with the circle (`centre`, `radius`)
// farthest along the ray; none when they do not meet ahead of the origin.
std::optional<Point> ray_circle_far(Point origin, double angle_deg, Point centre, double radius);

}  // namespace locus::relative
