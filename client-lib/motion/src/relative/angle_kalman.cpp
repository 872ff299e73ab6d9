#include "locus/motion/relative/angle_kalman.hpp"

#include <cmath>

namespace locus::relative {

double wrap_deg(double deg) {
    double w = std::fmod(deg, 360.0);
    if (w <= -180.0) w += 360.0;
    if (w > 180.0) w -= 360.0;
    return w;
}

double AngleKalman::update(double direction_deg) {
    const double z = wrap_deg(direction_deg);
    // As in the thesis, the first measurement is taken as is and leaves P at its initial value.
    if (!x_) {
        x_ = z;
        return *x_;
    }
    const double p_minus = p_ + params_.q;
    const double k = p_minus / (p_minus + params_.r);
    x_ = wrap_deg(*x_ + k * wrap_deg(z - *x_));
    p_ = (1.0 - k) * p_minus;
    return *x_;
}

void AngleKalman::reset() {
    x_.reset();
    p_ = params_.p0;
}

}  // namespace locus::relative
