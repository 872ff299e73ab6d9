#include "tracks/fusion.hpp"

#include <cmath>
#include <numbers>

namespace locus::tracks {

namespace {

// Degrees in [0, 360), as the step headings are answered.
double wrap_deg(double deg) {
    const double d = std::fmod(deg, 360.0);
    return d < 0.0 ? (d + 360.0 < 360.0 ? d + 360.0 : 0.0) : d;
}

}  // namespace

Eigen::Matrix2d fix_covariance(double accuracy_m) {
    const double s = std::max(accuracy_m, 0.5);  // a fix claiming centimetres would freeze the cloud
    return Eigen::Matrix2d::Identity() * (s * s);
}

fusion::RangingKalmanConfig kalman_config(FusionMethod method, const FusionOptions& options) {
    auto c = method == FusionMethod::kalman_trilateration ? fusion::trilateration_kalman_config() : fusion::ranging_kalman_config();
    if (options.r_sigma_m) c.fixed_r_sigma_m = *options.r_sigma_m;
    if (options.q_sigma_m) c.kalman.step_sigma_floor_m = *options.q_sigma_m;
    if (options.q_sigma_per_m) c.kalman.step_sigma_per_m = *options.q_sigma_per_m;
    if (options.r_floor_m) c.r_floor_m = *options.r_floor_m;
    if (options.r_scale) c.r_scale = *options.r_scale;
    return c;
}

fusion::RangingEkfConfig ekf_config(const FusionOptions& options) {
    fusion::RangingEkfConfig c;
    if (options.q_sigma_m) c.step_sigma_floor_m = *options.q_sigma_m;
    if (options.q_sigma_per_m) c.step_sigma_per_m = *options.q_sigma_per_m;
    if (options.reading_sigma_db) c.reading_sigma_db = *options.reading_sigma_db;
    if (options.step_lead_s) c.step_lead_s = *options.step_lead_s;
    if (options.offset_sigma_db) c.offset_sigma_db = *options.offset_sigma_db;
    if (options.heading_walk_rad_per_sqrt_m) c.heading_walk_rad_per_sqrt_m = *options.heading_walk_rad_per_sqrt_m;
    if (options.huber_k) c.huber_k = *options.huber_k;
    return c;
}

fusion::WalkFilterConfig walk_config(const FusionOptions& options, std::uint64_t seed, bool rotation_known) {
    fusion::WalkFilterConfig c = fusion::WalkFilterConfig::real_walks();
    c.seed = seed;
    if (rotation_known) c = fusion::WalkFilterConfig::known_rotation(c);
    if (options.step_scale) c.scale_mean = *options.step_scale;
    if (options.step_scale_sigma) c.scale_sigma = *options.step_scale_sigma;
    if (options.fix_sigma_m) c.fix_sigma_m = *options.fix_sigma_m;
    if (options.reseed_fraction) c.reseed_fraction = *options.reseed_fraction;
    if (options.reseed_max_fraction) c.reseed_max_fraction = *options.reseed_max_fraction;
    if (options.rotation_sigma_deg) c.hint_sigma_rad = *options.rotation_sigma_deg * std::numbers::pi / 180.0;
    if (options.rotation_walk_deg) c.offset_walk_rad = *options.rotation_walk_deg * std::numbers::pi / 180.0;
    return c;
}

ThinFusion::ThinFusion(FusionMethod method, std::uint64_t seed, const FusionOptions& options)
    : method_(method), options_(options) {
    config_.seed = seed;
    if (is_kalman(method)) kalman_config_ = kalman_config(method, options);
    if (method == FusionMethod::ekf_ranging) ekf_config_ = ekf_config(options);
}

Eigen::Matrix2d ThinFusion::kalman_r(const RadioFix& r) const {
    ranging::Fix f;
    if (r.ranged) {
        f = *r.ranged;
    } else {
        f.sxx = f.syy = r.accuracy_m * r.accuracy_m;
    }
    return fusion::ranging_measurement_noise(f, kalman_config_);
}

void ThinFusion::start(const fusion::Walkable* w, const RadioFix& r, bool resumed, std::optional<double> bearing_deg) {
    const Point at{r.x, r.y};
    if (method_ == FusionMethod::ekf_ranging) {
        // At the fix, as sure of it as the fix is (floored as a posted fix's R is); resumed, as
        // sure as the filter was then. The starting scan's readings are not used again: the
        // fix is made of them. The phone's offset and the heading bias start afresh (the
        // stored fix does not hold them).
        fusion::RangingEkfConfig c = ekf_config_;
        c.initial_sigma_m = resumed ? std::max(r.accuracy_m, 0.05) : std::max(r.accuracy_m, 0.5);
        static const std::vector<fusion::RangingAnchor> none;
        const std::vector<fusion::RangingAnchor>* anchors = &none;
        if (anchors_)
            if (const auto it = anchors_->by_floor.find(r.floor_id); it != anchors_->by_floor.end()) anchors = &it->second;
        ekf_.emplace(at, *anchors, c);
    } else if (is_kalman(method_)) {
        // The filter starts at the fix, as sure of it as the fix is (its R's mean σ per axis);
        // resumed at a stored fused fix, as sure as the filter was then.
        fusion::KalmanConfig c = kalman_config_.kalman;
        c.initial_sigma_m = resumed ? std::max(r.accuracy_m, 0.05) : std::sqrt(kalman_r(r).trace() / 2.0);
        // Ours is map-matched on the floor's plan as `locus replay` runs it; the paper's is not.
        std::shared_ptr<const fusion::PlanWalkable> plan;
        if (method_ == FusionMethod::kalman_ranging && w) plan = w->floor_plan;
        kalman_.emplace(at, c, std::move(plan));
    } else if (method_ == FusionMethod::walk_pf) {
        // A step's heading is the compass's azimuth, clockwise from north; the floor's +y axis
        // points bearing_deg clockwise from north, so the heading on the floor is the azimuth
        // less the bearing (docs/tracks.md). With rotation_sigma_deg the client turned it itself.
        std::optional<double> rotation_rad;
        if (options_.rotation_sigma_deg) rotation_rad = 0.0;
        else if (bearing_deg) rotation_rad = -*bearing_deg * std::numbers::pi / 180.0;
        walk_.emplace(w ? std::optional<fusion::Walkable>(*w) : std::nullopt, walk_config(options_, config_.seed, rotation_rad.has_value()));
        if (rotation_rad) walk_->hint(*rotation_rad, false);
        walk_->fix(at, fix_covariance(r.accuracy_m));
    } else {
        if (!w) throw std::invalid_argument("floor " + std::to_string(r.floor_id) + " has no plan: the particle filter walks on one (walk_pf does not need one)");
        filter_.emplace(*w, at, config_);
    }
    floor_id_ = r.floor_id;
}

bool ThinFusion::gnss_update(Point at, double sigma_m) {
    const Eigen::Matrix2d r = Eigen::Matrix2d::Identity() * (sigma_m * sigma_m);
    // The Kalman methods drop a fix beyond the gate, as `locus eval ipin`'s kalman does; the
    // particle filters' outlier floor keeps a far fix from ruling them.
    const auto within_gate = [&](Point p, const Eigen::Matrix2d& p_cov) {
        const Eigen::Vector2d d(at.x - p.x, at.y - p.y);
        return d.dot((p_cov + r).inverse() * d) <= fusion::kGnssGateChi2;
    };
    if (ekf_) {
        if (!within_gate(ekf_->position(), ekf_->position_covariance())) return false;
        ekf_->update_position(at, r);
    } else if (kalman_) {
        if (!within_gate(kalman_->position(), kalman_->covariance())) return false;
        kalman_->update(at, r);
    } else if (walk_) {
        walk_->fix(at, r);
    } else {
        filter_->update(at, r);
    }
    return true;
}

std::optional<int> ThinFusion::baro_index(std::int64_t floor_id) const {
    const auto it = std::find(baro_ids_.begin(), baro_ids_.end(), floor_id);
    if (it == baro_ids_.end()) return std::nullopt;
    return static_cast<int>(it - baro_ids_.begin());
}

std::size_t ThinFusion::memory_bytes() const {
    std::size_t n = sizeof(*this) + baro_ids_.capacity() * sizeof(std::int64_t);
    if (walk_) n += walk_->memory_bytes() - sizeof(fusion::WalkFilter);
    if (filter_) n += filter_->particles().capacity() * sizeof(filter_->particles().front());
    return n;
}

Fix ThinFusion::fused(double t, std::optional<double> heading_deg) const {
    Fix f;
    f.t = t;
    f.floor_id = floor_id_;
    f.heading_deg = heading_deg;
    if (ekf_) {
        // ekf_ranging estimates the compass's bias β and turns each step by it (counter-clockwise):
        // the heading walked is the step's less β, clockwise. The other methods answer it raw.
        if (heading_deg) f.heading_deg = wrap_deg(*heading_deg - ekf_->heading_bias_rad() * 180.0 / std::numbers::pi);
        const Point p = ekf_->position();
        f.x = p.x;
        f.y = p.y;
        f.accuracy_m = std::sqrt(ekf_->position_covariance().trace() / 2.0);
        return f;
    }
    if (kalman_) {
        const Point p = kalman_->position();
        f.x = p.x;
        f.y = p.y;
        f.accuracy_m = std::sqrt(kalman_->covariance().trace() / 2.0);  // σ per axis of an isotropic P alike
        return f;
    }
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
