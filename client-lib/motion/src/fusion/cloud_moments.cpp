#include "cloud_moments.hpp"

namespace locus::fusion {

CloudMoments cloud_moments(const float* x, const float* y, const float* w, std::size_t n, Point c, float r2) {
    float sw = 0.0f, sx = 0.0f, sy = 0.0f, sd = 0.0f;
    const float cx = static_cast<float>(c.x), cy = static_cast<float>(c.y);
    for (std::size_t i = 0; i < n; ++i) {
        const float dx = x[i] - cx, dy = y[i] - cy, d2 = dx * dx + dy * dy;
        const float wk = w[i] * static_cast<float>(d2 <= r2);  // a mask, not a branch, so the loop vectorises
        sw += wk, sx += wk * dx, sy += wk * dy, sd += wk * d2;
    }
    return {sw, sx, sy, sd};
}

}  // namespace locus::fusion
