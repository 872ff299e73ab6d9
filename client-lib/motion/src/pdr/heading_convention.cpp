#include "locus/motion/pdr/heading_convention.hpp"

#include <cmath>
#include <numbers>

namespace locus::pdr {

Point step(Point from, double length_m, double heading_rad) {
    return {from.x + length_m * std::sin(heading_rad), from.y + length_m * std::cos(heading_rad)};
}

double wrap_angle(double rad) {
    constexpr double two_pi = 2.0 * std::numbers::pi;
    double r = std::fmod(rad + std::numbers::pi, two_pi);
    if (r <= 0.0) r += two_pi;
    return r - std::numbers::pi;
}

}  // namespace locus::pdr
