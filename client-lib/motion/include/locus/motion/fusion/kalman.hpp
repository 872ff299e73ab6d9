#pragma once
// Position Kalman filter (docs/spec.md §6.9): state (x, y), the PDR step
// displacement is the control input, a WiFi fix is a direct measurement of the state.
//   predict: x ← x + u,            P ← P + Q(u)
//   update:  K = P (P + R)⁻¹,      x ← x + K (z − x),   P ← (I − K) P
// Q grows with the distance walked (heading and length errors scale with it); R comes from
// the matcher's candidate spread (fix_covariance).
//
// With a floor plan (map matching, docs/fusion.md): a fix outside walkable space is snapped
// into it before the update, and so is the posterior after it (on the fix's side of a wall
// it is caught in), and so is the state after each step. The posterior of an update may land
// on the other side of a wall: the fix is evidence of where the person is, not a movement,
// and a prior in the wrong room must be able to leave it. Steps may pass walls too unless
// walls_block_steps: one hypothesis that lags the person stays behind a wall the person went
// through (a door a metre further on), which cost the ground floor's final error more than
// the blocking gained (docs/fusion.md); the particle filter is the map matcher that blocks.
#include <Eigen/Dense>
#include <memory>
#include <span>

#include "locus/motion/fusion/plan_walkable.hpp"
#include "locus/geometry.hpp"

namespace locus::fusion {

// Noise defaults tuned on simulated walks with seeds 101..110 (docs/fusion.md).
struct KalmanConfig {
    double initial_sigma_m = 1.0;   // σ of the start position
    double step_sigma_floor_m = 0.05;   // per-step position noise even for a tiny step
    double step_sigma_per_m = 0.5;      // plus this much per metre walked...
    double disturbed_sigma_per_m = 1.0; // ...or this much while the PDR flags a magnetic disturbance
    // A fix whose Mahalanobis distance² exceeds this is rejected as an outlier (χ², 2 dof:
    // 13.8 ≈ 0.1 %). ≤ 0 disables the gate.
    double gate_chi2 = 0.0;
    // With a floor plan: true stops a step at the wall it would cross (PlanWalkable::step:
    // it slides along the wall, or goes round a door jamb it clipped); false only snaps where
    // the step ends into walkable space.
    bool walls_block_steps = false;
};

class KalmanFilter {
public:
    explicit KalmanFilter(Point start, const KalmanConfig& config = {},
                          std::shared_ptr<const PlanWalkable> floor_plan = nullptr);

    void predict(Point displacement, bool magnetic_disturbance = false);
    // Returns false when the gate rejected the fix (state unchanged).
    bool update(Point fix, const Eigen::Matrix2d& r);

    Point position() const { return {x_.x(), x_.y()}; }
    const Eigen::Matrix2d& covariance() const { return p_; }

private:
    KalmanConfig config_;
    std::shared_ptr<const PlanWalkable> floor_plan_;
    Eigen::Vector2d x_;
    Eigen::Matrix2d p_;
};

// Covariance of a fix from the positions of the matcher's top candidates, weighted (weights
// need not sum to 1; empty weights = equal). The spread says how ambiguous the radio match
// was; each axis variance is raised to at least floor_m² so a single candidate (zero spread)
// is not taken as exact.
Eigen::Matrix2d fix_covariance(std::span<const Point> candidates, std::span<const double> weights, double floor_m);

}  // namespace locus::fusion
