#pragma once
// Bonjorn López 2016's 1-D Kalman filter on an angle (degrees): the state is the direction of a target
// taken as static (F = H = 1, no control), so only the gain shrinks as measurements come in.
// Innovations and the estimate wrap at ±180° so that 179° and −179° are neighbours.
#include <optional>

namespace locus::relative {

struct AngleKalmanParams {
    // The thesis's initialisation (its appendix): process noise Q, measurement noise R, P0.
    double q = 1e-5;
    double r = 1e-3;
    double p0 = 1.0;
};

class AngleKalman {
public:
    explicit AngleKalman(AngleKalmanParams p = {}) : params_(p), p_(p.p0) {}

    // Folds in one direction measurement (degrees); answers the estimate in (−180°, 180°].
    double update(double direction_deg);
    std::optional<double> estimate() const { return x_; }
    void reset();

private:
    AngleKalmanParams params_;
    std::optional<double> x_;
    double p_;
};

// `deg` folded into (−180°, 180°].
double wrap_deg(double deg);

}  // namespace locus::relative
