#include "sim/walk.hpp"

#include <algorithm>

namespace locus::sim {

bool Walk::has_truth() const {
    return !imu.empty() && std::all_of(imu.begin(), imu.end(), [](const ImuSample& s) { return s.truth.has_value(); });
}

std::optional<Point> Walk::truth_at(double t_s) const {
    if (imu.empty()) return std::nullopt;
    auto it = std::lower_bound(imu.begin(), imu.end(), t_s, [](const ImuSample& s, double t) { return s.t_s < t; });
    if (it == imu.begin()) return it->truth;
    if (it == imu.end()) return imu.back().truth;
    const ImuSample& b = *it;
    const ImuSample& a = *(it - 1);
    if (!a.truth || !b.truth) return std::nullopt;
    const double u = b.t_s > a.t_s ? (t_s - a.t_s) / (b.t_s - a.t_s) : 0.0;
    return Point{a.truth->x + u * (b.truth->x - a.truth->x), a.truth->y + u * (b.truth->y - a.truth->y)};
}

}  // namespace locus::sim
