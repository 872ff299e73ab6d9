#include "ipin_track.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "locus/motion/fusion/heading_alignment.hpp"
#include "locus/motion/fusion/walk_runner.hpp"
#include "locus/motion/pdr/step_detector.hpp"
#include "locus/motion/pdr/step_length.hpp"

namespace locus::tools::ipin {

std::vector<ImuStep> log_steps(const datasets::ipin::Log& log) {
    std::vector<ImuStep> out;
    if (log.ahrs.empty()) return out;
    pdr::StepDetector detector;
    const pdr::StepLengthModel length;
    // The rotation vector's yaw grows counter-clockwise from north (the data set's README):
    // the compass azimuth, clockwise, is its negative. The sample in force at a step's time is
    // the last one received at or before it.
    auto azimuth_at = [&](double t) {
        auto it = std::upper_bound(log.ahrs.begin(), log.ahrs.end(), t,
                                   [](double v, const datasets::ipin::Ahrs& a) { return v < a.app_s; });
        const auto& a = it == log.ahrs.begin() ? *it : *(it - 1);
        return -a.yaw_deg * std::numbers::pi / 180.0;
    };
    for (const auto& s : datasets::ipin::accel_samples(log)) {
        auto e = detector.push(s.t_s, s.ax, s.ay, s.az);
        while (e) {
            // A bout confirms several steps at once: each is known now, each points where the
            // phone pointed when it was taken.
            out.push_back({s.t_s, length.length(*e), azimuth_at(e->t_s)});
            e = detector.poll();
        }
    }
    return out;
}

namespace {

// The tracker's horizontal state: the walk filter or dead reckoning, both beginning at a point.
class Horizontal {
public:
    Horizontal(Tracker kind, const TrackerConfig& config)
        : kind_(kind), config_(config), wf_(std::nullopt, config.walk_filter) {}

    bool begun() const { return begun_; }
    Point position() const { return kind_ == Tracker::walk_pf ? wf_.position() : at_; }

    // Begins at a point: a known start (tight) or the first answer (its σ).
    void begin(Point at, double sigma_m) {
        begun_ = true;
        at_ = at;
        align_.add_fix(at);
        if (kind_ == Tracker::walk_pf) wf_.fix(at, Eigen::Matrix2d::Identity() * sigma_m * sigma_m);
    }
    void step(const ImuStep& s) {
        if (!begun_) return;
        align_.add_step(s.length_m, s.azimuth_rad);
        if (kind_ == Tracker::walk_pf) {
            wf_.step(s.length_m, s.azimuth_rad);
            return;
        }
        const bool aligned = align_.pairs() >= config_.alignment_pairs;
        const double heading = align_.floor_heading(s.azimuth_rad);
        const double len = s.length_m * (aligned && align_.scale() > 0.0 ? align_.scale() : 1.0);
        at_ = {at_.x + len * std::sin(heading), at_.y + len * std::cos(heading)};
    }
    void answer(Point at) {
        if (!begun_) {
            begin(at, config_.answer_sigma_m);
            return;
        }
        align_.add_fix(at);
        if (kind_ != Tracker::walk_pf) return;
        if (align_.pairs() >= config_.alignment_pairs) wf_.hint(align_.offset_rad(), align_.mirrored());
        wf_.fix(at, Eigen::Matrix2d::Identity() * config_.answer_sigma_m * config_.answer_sigma_m);
    }

private:
    Tracker kind_;
    TrackerConfig config_;
    fusion::WalkFilter wf_;
    fusion::HeadingAlignment align_;
    Point at_;
    bool begun_ = false;
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
    std::vector<double> step_t;
    step_t.reserve(in.steps.size());
    for (const auto& s : in.steps) step_t.push_back(s.t_s);
    std::vector<Fix> out;
    fusion::WalkHandlers handlers;
    handlers.pressure = [&](std::size_t k) {
        if (baro) baro->add_pressure(in.pressure[k].t_s, in.pressure[k].hpa);
    };
    handlers.step = [&](std::size_t i) {
        if (walking(in.steps[i].t_s)) h.step(in.steps[i]);
    };
    handlers.fix = [&](std::size_t i) {
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
    fusion::run_walk({.pressure = pressure_t, .step = step_t, .fix = in.scan_times, .tick = ticks}, handlers);
    return out;
}

}  // namespace locus::tools::ipin
