#pragma once
// Tightly coupled ranging + PDR filter (for the scenario of the Kalman-fusion paper, docs/spec.md
// §8): an extended Kalman filter whose measurements are the anchors' raw readings themselves, not
// positions fitted from averaged readings. Multilateration happens inside the update:
//   state   s = [x, y, b, β]: position (m), the phone's RSS offset b (dB, what its radio adds
//           to every anchor alike) and the PDR heading's bias β (rad, the compass's drift)
//   predict s.xy ← s.xy + R(β)·u for each PDR step u;  P ← F P Fᵀ + Q(|u|), b and β random walks
//   update  z_i = rss_i, h_i(s) = tx_power_i − 10·n_i·log10(d_i(x, y)) + b, for the readings of
//           one instant together: an iterated EKF update (Gauss–Newton on the posterior), each
//           reading's variance inflated by a Huber weight when its innovation is far out
// Why: the loose coupling (multilateration of 5 s averages fed to KalmanFilter) treats a window
// as if the phone stood still in it and its fix as independent of the prior; here each reading
// is used at its own time with the position the steps give then, and the prior regularises
// the geometry (a fix from six anchors in a line-like layout is poor along the line).
// Pure: no I/O; an update allocates only its scan's small matrices.
#include <Eigen/Dense>
#include <deque>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/ranging/path_loss.hpp"

namespace locus::fusion {

// An anchor as a floor's transmitter list states it: id (bssid, beacon id), position, height
// above the phone (`dz`) and its log-distance model.
struct RangingAnchor {
    std::string id;
    ranging::Transmitter tx;
};

// One reading of one anchor.
struct AnchorReading {
    std::string anchor_id;
    double t_s = 0.0;
    double rss = 0.0;  // dBm
};

// Defaults tuned on `locus sim --scenario open_area` walks 101..160, checked on 161..200 and 206..260
// (docs/transmitters.md).
struct RangingEkfConfig {
    double initial_sigma_m = 1.0;          // σ of the start position per axis
    double offset_sigma_db = 3.0;          // prior σ of the phone's RSS offset (phone models differ by a few dB)
    double offset_walk_db_per_sqrt_s = 0.0;// the offset's random walk (the radio's drift, the hand's grip)
    bool estimate_heading_bias = true;     // β in the state (else fixed at 0): 0.99 → 0.92 m on the tuning walks
    double heading_bias_sigma_rad = 0.05;  // prior σ of β
    double heading_walk_rad_per_sqrt_m = 0.04;  // β's random walk per √metre walked (the compass's drift)
    double step_sigma_floor_m = 0.05;      // position noise per step even for a tiny step
    double step_sigma_per_m = 0.1;         // plus this much per metre walked (length and heading errors)
    // A reading at time t is evaluated where the phone was before the steps stamped in
    // (t − this, t]: the PDR stamps a step before the phone has made all of it (about 0.2 s on the
    // simulated walker), and 0.7 s was best on the tuning walks (0.87 → 0.79 m; 0 turns it off).
    double step_lead_s = 0.7;
    double reading_sigma_db = 4.0;         // σ of one reading about the model (noise + shadowing + model error)
    double huber_k = 1.5;                  // innovations beyond huber_k·σ are down-weighted (Huber)
    int iterations = 3;                    // Gauss–Newton iterations of one update (1 = plain EKF)
    double min_range_m = 0.5;              // horizontal distance floor in h's Jacobian (near an anchor)
};

class RangingEkf {
public:
    // Anchors with the same id: the last one wins. Throws std::invalid_argument for a config
    // whose reading_sigma_db, huber_k or min_range_m is not positive or iterations below 1.
    RangingEkf(Point start, std::span<const RangingAnchor> anchors, const RangingEkfConfig& config = {});

    // One PDR step: its displacement as the PDR gives it (rotated by the heading-bias state when
    // estimated), stamped t_s (for the offset's random walk and the step lead).
    void predict(Point displacement, double t_s);
    // The readings of one instant (one scan); readings of unknown anchors are ignored. Returns the
    // number of readings used.
    int update(std::span<const AnchorReading> readings);
    // A position fix from elsewhere (a radio-map match, a QR code at a door) with covariance r
    // (m²): a linear update of x, y (the offset and the heading bias move only through their
    // correlation with the position).
    void update_position(Point at, const Eigen::Matrix2d& r);

    Point position() const { return {s_(0), s_(1)}; }
    double offset_db() const { return s_(2); }
    double heading_bias_rad() const { return s_(3); }
    // Position covariance (m²).
    Eigen::Matrix2d position_covariance() const { return p_.topLeftCorner<2, 2>(); }
    const Eigen::Matrix4d& covariance() const { return p_; }

private:
    void advance_time(double t_s);

    RangingEkfConfig config_;
    // Where the position was this-much before: the displacement of the steps stamped after t.
    Eigen::Vector2d moved_since(double t_s) const;

    std::unordered_map<std::string, ranging::Transmitter> anchors_;
    std::deque<std::pair<double, Eigen::Vector2d>> recent_steps_;  // (stamp, displacement) within step_lead_s
    Eigen::Vector4d s_;
    Eigen::Matrix4d p_;
    double t_s_ = 0.0;
    bool has_time_ = false;
};

}  // namespace locus::fusion
