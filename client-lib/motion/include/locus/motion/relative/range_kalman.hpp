#pragma once
// A Kalman filter on the A–B distance driven by A's own PDR (Bonjorn López 2016, docs/spec.md §8,
// with RSSI): one RSSI distance is ±40 % at 4 dB shadowing, so the estimator's weights (d_0 −
// d_k)/Δρ are noise unless the distances are smoothed. B stands still, so while A walks the
// distance changes by (about) v metres per metre walked, v = −cos(angle between A's walk and B):
// the state is (d, v), the prediction moves d by v × the step's length, and each RSSI distance is a
// measurement of ln d (the shadowing is Gaussian in dB, so in ln d too). An acoustic range
// (centimetres, close by) is a measurement of d itself.
#include <optional>

namespace locus::relative {

struct RangeKalmanParams {
    double ln_sigma = 0.37;        // σ of ln(RSSI distance): ln 10 × 4 dB / (10 × 2.5)
    double d_walk_sigma = 0.05;    // per metre walked: what the linear model misses of d
    double v_walk_sigma = 0.08;    // per metre walked: how fast v drifts (turns, passing B)
    double v0_sigma = 1.0;         // nothing known of the walk's angle to B at the start
};

class RangeKalman {
public:
    explicit RangeKalman(RangeKalmanParams p = {}) : params_(p) {}

    // A walked `step_m` metres (PDR) since the last call.
    void predict(double step_m);
    // One distance from RSSI (m, > 0).
    void update_rssi(double distance_m);
    // One distance measured directly with σ `sigma_m` (acoustic ranging).
    void update_direct(double distance_m, double sigma_m);

    // The filtered distance (m), none before the first measurement.
    std::optional<double> distance() const;
    // Distance change per metre walked (−1: walking straight at B).
    double rate() const { return v_; }

private:
    void update(double innovation, double h_d, double r);

    RangeKalmanParams params_;
    bool started_ = false;
    double d_ = 0, v_ = 0;
    double p_dd_ = 0, p_dv_ = 0, p_vv_ = 0;
};

}  // namespace locus::relative
