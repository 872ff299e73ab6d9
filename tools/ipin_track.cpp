#include "ipin_track.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "locus/motion/fusion/heading_alignment.hpp"
#include "locus/motion/fusion/kalman.hpp"
#include "locus/motion/fusion/walk_runner.hpp"

namespace locus::tools::ipin {

namespace {

// The gyroscope's turn about the vertical, integrated: a compass azimuth (clockwise, rad) with
// an arbitrary origin, sampled at each GYRO sample. The vertical is the low-passed
// accelerometer (gravity included, so it points up); the turn rate about it is ω·up, counter-
// clockwise, so the clockwise azimuth falls by it.
std::vector<std::pair<double, double>> gyro_azimuth(const datasets::ipin::Log& log) {
    constexpr double kGravityAlpha = 0.1;
    constexpr double kMaxGapS = 0.2;  // a longer gap in the samples is not integrated over
    std::vector<std::pair<double, double>> out;
    std::optional<pdr::Vec3> gravity;
    std::optional<double> last_t;
    double azimuth = 0.0;
    for (const auto& s : datasets::ipin::imu_samples(log)) {
        if (s.sensor == datasets::ImuSensor::acc) {
            gravity = gravity ? (1.0 - kGravityAlpha) * *gravity + kGravityAlpha * s.v : s.v;
        } else if (s.sensor == datasets::ImuSensor::gyro && gravity && pdr::norm(*gravity) > 0.0) {
            const double dt = last_t ? s.t_s - *last_t : 0.0;
            if (dt > 0.0 && dt < kMaxGapS) azimuth -= pdr::dot(s.v, (1.0 / pdr::norm(*gravity)) * *gravity) * dt;
            last_t = s.t_s;
            out.emplace_back(s.t_s, azimuth);
        }
    }
    return out;
}

}  // namespace

std::vector<ImuStep> log_steps(const datasets::ipin::Log& log, HeadingSource source) {
    // The azimuth series: the rotation vector's yaw grows counter-clockwise from north (the
    // data set's README), so the clockwise azimuth is its negative; or the gyroscope's.
    std::vector<std::pair<double, double>> series;
    if (source == HeadingSource::gyro) {
        series = gyro_azimuth(log);
    } else {
        for (const auto& a : log.ahrs) series.emplace_back(a.app_s, -a.yaw_deg * std::numbers::pi / 180.0);
    }
    if (series.empty()) return {};
    const auto accel = [](const datasets::AccelSample& s) { return std::array{s.t_s, s.ax, s.ay, s.az}; };
    const auto azimuth_at = [&](double t) {
        return sample_at(series, t, [](const std::pair<double, double>& a) { return a.first; }).second;
    };
    return detect_phone_steps(datasets::ipin::accel_samples(log), accel, azimuth_at);
}

std::vector<BleReading> log_ble(const datasets::ipin::Log& log) {
    std::vector<BleReading> out;
    out.reserve(log.ble4.size());
    for (const auto& b : log.ble4) out.push_back({b.app_s, b.mac, b.rssi_dbm});
    std::stable_sort(out.begin(), out.end(), [](const BleReading& a, const BleReading& b) { return a.t < b.t; });
    return out;
}

std::vector<BeaconFix> beacon_fixes(std::span<const BleReading> readings, std::span<const Beacon> beacons,
                                    const TrackerConfig& config) {
    std::vector<BeaconFix> out;
    fusion::BeaconGate gate(config.ble_min_interval_s);
    for (const auto& r : readings) {
        if (!(r.rss_dbm >= config.ble_min_rss_dbm)) continue;
        for (const auto& b : beacons) {
            if (b.mac != r.mac) continue;
            if (gate.take(b.mac.str(), r.t)) out.push_back({r.t, b.floor, b.at});
            break;
        }
    }
    return out;
}

namespace {

// The tracker's horizontal state: the Kalman filter or dead reckoning, each beginning at a point.
class Horizontal {
public:
    Horizontal(Tracker kind, const TrackerConfig& config) : kind_(kind), config_(config) {}

    bool begun() const { return begun_; }
    Point position() const { return kind_ == Tracker::kalman ? kf_->position() : at_; }

    // Begins at a point: a known start (tight) or the first answer (its σ).
    void begin(Point at, double sigma_m) {
        begun_ = true;
        at_ = at;
        align_.add_fix(at);
        fusion::KalmanConfig kc = config_.kalman;
        kc.initial_sigma_m = sigma_m;
        if (kind_ == Tracker::kalman) kf_.emplace(at, kc);
    }
    void step(const ImuStep& s) {
        if (!begun_) return;
        align_.add_step(s.length_m, s.azimuth_rad);
        // In the venue's frame: the known rotation, else the one learnt from the answers; the
        // step scaled by the answers' distance ratio once it is fitted.
        const bool aligned = align_.pairs() >= config_.alignment_pairs;
        const double heading = config_.compass_offset_rad ? *config_.compass_offset_rad + s.azimuth_rad : align_.floor_heading(s.azimuth_rad);
        const double len = s.length_m * (aligned && align_.scale() > 0.0 ? align_.scale() : config_.step_scale);
        const Point d{len * std::sin(heading), len * std::cos(heading)};
        if (kind_ == Tracker::kalman) kf_->predict(d);
        else at_ = {at_.x + d.x, at_.y + d.y};
    }
    void answer(Point at) {
        if (!begun_) {
            begin(at, config_.answer_sigma_m);
            return;
        }
        align_.add_fix(at);
        if (kind_ == Tracker::kalman) kf_->update(at, Eigen::Matrix2d::Identity() * config_.answer_sigma_m * config_.answer_sigma_m);
    }

    void gnss(const GnssFix& g) {
        if (!begun_ || kind_ == Tracker::pdr) return;
        if (last_gnss_s_ && g.t - *last_gnss_s_ < config_.gnss_min_interval_s) return;
        last_gnss_s_ = g.t;
        measure(g.at, std::max(g.accuracy_m, config_.gnss_min_sigma_m));
    }
    void beacon(const BeaconFix& b) {
        if (begun_ && kind_ != Tracker::pdr) measure(b.at, config_.ble_sigma_m);
    }

private:
    // A position measurement that is not a WiFi answer (GNSS, a beacon): it teaches the heading
    // alignment nothing, and kalman drops it beyond the gate.
    void measure(Point at, double sigma_m) {
        const Eigen::Matrix2d r = Eigen::Matrix2d::Identity() * sigma_m * sigma_m;
        const Eigen::Vector2d d(at.x - kf_->position().x, at.y - kf_->position().y);
        if (d.dot((kf_->covariance() + r).inverse() * d) <= config_.gnss_gate) kf_->update(at, r);
    }

    Tracker kind_;
    TrackerConfig config_;
    std::optional<fusion::KalmanFilter> kf_;
    fusion::HeadingAlignment align_;
    Point at_;
    bool begun_ = false;
    std::optional<double> last_gnss_s_;
};

bool has_floor(const std::vector<fusion::FloorLevel>& floors, int floor) {
    return std::any_of(floors.begin(), floors.end(), [&](const fusion::FloorLevel& f) { return f.floor == floor; });
}

}  // namespace

std::vector<Fix> track(Tracker tracker, const TrackInput& in, const std::vector<fusion::FloorLevel>& floors,
                       const TrackerConfig& config) {
    std::optional<fusion::BaroFloor> baro;
    if (!floors.empty()) {
        std::optional<int> start_floor;
        if (in.start && has_floor(floors, in.start->floor)) start_floor = in.start->floor;
        baro.emplace(floors, fusion::BaroFloorConfig{}, start_floor);
    }
    std::vector<double> ticks;
    for (double t = 0.0; t <= in.end_s; t += config.tick_s) ticks.push_back(t);

    Horizontal h(tracker, config);
    std::optional<int> radio_floor = in.start ? std::optional<int>(in.start->floor) : std::nullopt;
    // With a known start the walker stands on it until its time (the calibration minute):
    // steps and answers before then move nothing; the barometer takes everything.
    auto walking = [&](double t) {
        if (!in.start) return true;
        if (!h.begun() && t >= in.start->t) h.begin(in.start->at, 0.5);
        return h.begun();
    };
    const std::vector<double> step_t = fusion::times_of(in.steps, &ImuStep::t_s);
    std::vector<Fix> out;
    fusion::WalkHandlers handlers;
    handlers.pressure = [&](std::size_t k) {
        if (baro) baro->add_pressure(in.pressure[k].t_s, in.pressure[k].hpa);
    };
    handlers.step = [&](std::size_t i) {
        if (walking(in.steps[i].t_s)) h.step(in.steps[i]);
    };
    // The fix stream holds the scans' answers, the GNSS fixes and the beacon fixes, merged by
    // time (at equal times a scan first, then GNSS, then a beacon).
    enum Source : std::size_t { kScan, kGnss, kBle };  // merge_sources' order
    const std::vector<double> gnss_t = fusion::times_of(in.gnss, &GnssFix::t), ble_t = fusion::times_of(in.ble, &BeaconFix::t);
    const fusion::MergedStream fixes = fusion::merge_sources({in.scan_times, gnss_t, ble_t});
    handlers.fix = [&](std::size_t k) {
        const double t = fixes.t[k];
        const std::size_t i = fixes.index[k];
        if (fixes.source[k] == kGnss) {
            if (walking(t)) h.gnss(in.gnss[i]);
            return;
        }
        if (fixes.source[k] == kBle) {
            if (baro) baro->add_radio_vote(in.ble[i].floor);
            radio_floor = in.ble[i].floor;
            if (walking(t)) h.beacon(in.ble[i]);
            return;
        }
        const auto& a = in.answers[i];
        if (!a) return;
        if (baro) baro->add_radio_vote(a->floor);
        radio_floor = a->floor;
        if (walking(a->t)) h.answer(a->at);
    };
    handlers.tick = [&](std::size_t k) {
        const double t = ticks[k];
        walking(t);
        const std::optional<int> floor = baro && baro->floor() ? baro->floor() : radio_floor;
        if (!floor) return;
        if (h.begun()) out.push_back({t, *floor, h.position()});
        else if (in.start) out.push_back({t, *floor, in.start->at});
    };
    const std::vector<double> pressure_t = fusion::times_of(in.pressure, &datasets::ipin::PressureSample::t_s);
    fusion::run_walk({.pressure = pressure_t, .step = step_t, .fix = fixes.t, .tick = ticks}, handlers);
    return out;
}

}  // namespace locus::tools::ipin
