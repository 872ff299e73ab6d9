#include "locus/motion/pdr/compass.hpp"

#include <cmath>

namespace locus::pdr {

std::optional<double> compass_azimuth(Vec3 gravity, Vec3 magnetic) {
    // getRotationMatrix: H = E × A points east, M = A × H points north, A is up.
    const double an = norm(gravity);
    if (an < 0.1 * 9.80665) return std::nullopt;  // free fall: no vertical reference
    const Vec3 up = (1.0 / an) * gravity;
    Vec3 east = cross(magnetic, up);
    const double en = norm(east);
    if (en < 1e-9 || en < 0.1 * norm(magnetic)) return std::nullopt;  // field almost vertical
    east = (1.0 / en) * east;
    const Vec3 north = cross(up, east);

    // Device +y unless it points within ~25° of vertical (sin 25° ≈ 0.42 of horizontal length).
    Vec3 axis{0.0, 1.0, 0.0};
    if (std::hypot(east.y, north.y) < 0.42) axis = {0.0, 0.0, -1.0};
    return std::atan2(dot(axis, east), dot(axis, north));
}

Vec3 LowPass3::push(Vec3 in) {
    if (!ready_) {
        out_ = in;
        ready_ = true;
    } else {
        out_ = out_ + alpha_ * (in - out_);
    }
    return out_;
}

}  // namespace locus::pdr
