#pragma once
// The sums a particle cloud's estimate is made of (WalkFilter::estimate: the weighted mean, each
// mean-shift pass, the spread), over the particles' float arrays. Compiled on its own with
// the sums allowed to be reordered (client-lib/CMakeLists.txt), so that they run in vector
// lanes: about four times faster than one running sum, and they differ from it in their last
// bits only. O(n).
#include <cstddef>

#include "locus/geometry.hpp"

namespace locus::fusion {

struct CloudMoments {
    double w = 0.0, x = 0.0, y = 0.0, d2 = 0.0;  // Σ w, Σ w·dx, Σ w·dy, Σ w·(dx² + dy²)
};

// Over the particles within √r2 of c (every one when r2 is infinite), d = p − c, in float:
// ample for sums relative to c.
CloudMoments cloud_moments(const float* x, const float* y, const float* w, std::size_t n, Point c, float r2);

}  // namespace locus::fusion
