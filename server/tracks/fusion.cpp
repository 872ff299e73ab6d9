#include "tracks/fusion.hpp"

#include <cmath>

namespace locus::tracks {

Eigen::Matrix2d fix_covariance(double accuracy_m) {
    const double s = std::max(accuracy_m, 0.5);  // a fix claiming centimetres would freeze the cloud
    return Eigen::Matrix2d::Identity() * (s * s);
}

ThinFusion::ThinFusion(FusionMethod method, std::uint64_t seed)
    : method_(method), walk_config_(fusion::WalkFilterConfig::real_walks()) {
    config_.seed = seed;
    walk_config_.seed = seed;
}

void ThinFusion::start(const fusion::Walkable* w, const RadioFix& r) {
    const Point at{r.x, r.y};
    if (method_ == FusionMethod::walk_pf) {
        walk_.emplace(w ? std::optional<fusion::Walkable>(*w) : std::nullopt, walk_config_);
        walk_->fix(at, fix_covariance(r.accuracy_m));
    } else {
        if (!w) throw std::invalid_argument("floor " + std::to_string(r.floor_id) + " has no plan: the particle filter walks on one (walk_pf does not need one)");
        filter_.emplace(*w, at, config_);
    }
    floor_id_ = r.floor_id;
}

Fix ThinFusion::fused(double t, std::optional<double> heading_deg) const {
    Fix f;
    f.t = t;
    f.floor_id = floor_id_;
    f.heading_deg = heading_deg;
    if (walk_) {
        const Point p = walk_->position();
        f.x = p.x;
        f.y = p.y;
        f.accuracy_m = walk_->spread();
        return f;
    }
    const Point p = filter_->position();
    // The spread of the cloud: the weighted RMS distance of the particles from their mean.
    double sum = 0, weights = 0;
    for (const auto& q : filter_->particles()) {
        sum += q.weight * ((q.at.x - p.x) * (q.at.x - p.x) + (q.at.y - p.y) * (q.at.y - p.y));
        weights += q.weight;
    }
    f.x = p.x;
    f.y = p.y;
    f.accuracy_m = weights > 0 ? std::sqrt(sum / weights) : 0.0;
    return f;
}

}  // namespace locus::tracks
