#pragma once
// docs/spec.md §2.2 heading convention, used everywhere in the client library: θ is the azimuth in
// radians measured clockwise from the floor's +y axis ("local north"). A step of length D at
// heading θ moves x += D·sin θ, y += D·cos θ. (Traini 2017's math angle Θ = 90° − θ.)
#include "locus/geometry.hpp"

namespace locus::pdr {

Point step(Point from, double length_m, double heading_rad);

// Wraps an angle to (−π, π].
double wrap_angle(double rad);

}  // namespace locus::pdr
