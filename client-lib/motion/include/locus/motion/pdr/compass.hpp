#pragma once
// Tilt-compensated compass (docs/spec.md §5.4): the maths of Android's SensorManager.getRotationMatrix +
// getOrientation, in the docs/spec.md §2.2 convention (clockwise from north, radians).
#include <optional>

#include "locus/motion/pdr/vec3.hpp"

namespace locus::pdr {

// Azimuth of the device's +y axis (top of the screen), clockwise from magnetic north, from the
// accelerometer's gravity reading (points up when at rest) and the magnetic field, both in the
// device frame. When the phone is held upright (+y within ~25° of vertical) the +y axis has no
// useful horizontal direction, so the back of the phone (−z) is used instead: the direction
// the camera looks. Returns nothing when the inputs are degenerate (free fall, field parallel to
// gravity).
std::optional<double> compass_azimuth(Vec3 gravity, Vec3 magnetic);

// The docs/spec.md §5.4 low-pass: out += alpha·(in − out), alpha = 0.2 by default; the first sample
// initialises the output.
class LowPass3 {
public:
    explicit LowPass3(double alpha = 0.2) : alpha_(alpha) {}
    Vec3 push(Vec3 in);
    Vec3 value() const { return out_; }
    bool ready() const { return ready_; }
    void reset() { ready_ = false; }

private:
    double alpha_;
    Vec3 out_{};
    bool ready_ = false;
};

}  // namespace locus::pdr
