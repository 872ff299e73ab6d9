#include "tracks/fusion.hpp"

#include <cmath>

namespace locus::tracks {

Eigen::Matrix2d fix_covariance(double accuracy_m) {
    const double s = std::max(accuracy_m, 0.5);  // a fix claiming centimetres would freeze the cloud
    return Eigen::Matrix2d::Identity() * (s * s);
}

Fix ThinFusion::fused(double t, std::optional<double> heading_deg) const {
    const Point p = filter_->position();
    // The spread of the cloud: the weighted RMS distance of the particles from their mean.
    double sum = 0, weights = 0;
    for (const auto& q : filter_->particles()) {
        sum += q.weight * ((q.at.x - p.x) * (q.at.x - p.x) + (q.at.y - p.y) * (q.at.y - p.y));
        weights += q.weight;
    }
    Fix f;
    f.t = t;
    f.floor_id = floor_id_;
    f.x = p.x;
    f.y = p.y;
    f.accuracy_m = weights > 0 ? std::sqrt(sum / weights) : 0.0;
    f.heading_deg = heading_deg;
    return f;
}

}  // namespace locus::tracks
