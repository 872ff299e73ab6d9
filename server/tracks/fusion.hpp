#pragma once
// Fusion for thin clients (a web page, a phone without client-lib): they post raw PDR steps
// and radio fixes, and the server runs client-lib's filter (locus::fusion, the very code a
// phone with the library runs, never a second copy) and stores the fused fixes on the track.
// By default that is walk_pf (fusion::WalkFilter with the real-walk preset, the best causal
// method on real walks: docs/fusion.md), which learns the compass's rotation, mirror and the
// step scale and walks the floor's plan when it has one, freely when not; a track may ask for
// the older fusion::ParticleFilter, which needs a plan, or the Kalman-fusion paper's Kalman filter
// (fusion::KalmanFilter with PDR steps as control input, as `locus sim` and `locus replay` run
// it: kalman_trilateration with constant R and Q, kalman_ranging with each ranged fix's covariance as R;
// the latter map-matched on the floor's plan when it has one), or our tightly coupled
// fusion::RangingEkf (ekf_ranging: each known transmitter a scan hears is a measurement, so a
// scan hearing one or two still counts once the filter runs). One filter per track, started at
// its first radio fix and restarted at a radio fix on another floor, seeded with the track's id
// so a track's fused fixes are reproducible.
//
// Floors from the barometer. A track whose client posts pressure samples, on a building with two
// or more floors that have an `elevation_m`, also runs fusion::BaroFloor, the estimator
// `locus eval ipin`'s trackers run (the walk's relative pressure, the floors' elevations, each
// radio fix's floor as a vote): the track's floor is then the barometer's. A floor change it
// sees moves the filter to the new floor where it is (walk_pf keeps its cloud and what it has
// learnt; the other methods restart there, as sure as they were), and a radio fix on a floor it
// rules out moves nothing (its vote counts). Where the floor's plan has stairs or lifts to the
// new floor (connectors linked both ways, as routes take them), the walker went by the nearest:
// the filter comes out at its other end, shifted as the walker stood from it; where it has none
// (no plan, or none to that floor), the change happens where the walker is, the floors of a
// building taken to share one frame (as `locus import ipin` makes them). Without pressure
// samples, or on a building whose floors have no elevations, floors change at radio fixes alone.
//
// GNSS and the phone's offset (docs/tracks.md, "GNSS and the phone's offset"). A GNSS fix names
// no floor: it is taken on the filter's floor, through that floor's georeference (a floor with
// none takes no GNSS), as a position measurement of σ its accuracy, at least
// fusion::kGnssMinSigmaM, one per fusion::kGnssMinIntervalS at most, gated for the Kalman
// methods (the settings `locus eval ipin`'s trackers run, locus/motion/fusion/gnss.hpp). It never
// starts the filter. A walk_pf track also learns its phone's RSS offset (match::DeviceOffset)
// and counts each of the map's beacons once per interval (docs/tracks.md, "Beacons"), held here
// with the filter (tracks/scan_memory.hpp) so that each scan teaches once, in time order, and
// starts afresh where the filter does (a resume at a stored fix).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include <stdexcept>
#include <string>

#include "locus/geo/georeference.hpp"
#include "locus/match/device_offset.hpp"
#include "locus/motion/fusion/baro_floor.hpp"
#include "locus/motion/fusion/gnss.hpp"
#include "locus/motion/fusion/kalman.hpp"
#include "locus/motion/fusion/particle_filter.hpp"
#include "locus/motion/fusion/ranging_ekf.hpp"
#include "locus/motion/fusion/ranging_fix.hpp"
#include "locus/motion/fusion/walk_filter.hpp"
#include "locus/motion/fusion/walk_runner.hpp"
#include "locus/motion/pdr/heading_convention.hpp"
#include "locus/ranging/trilateration.hpp"
#include "tracks/fix.hpp"
#include "tracks/fusion_method.hpp"
#include "tracks/fusion_options.hpp"
#include "tracks/scan_memory.hpp"

namespace locus::tracks {

// A fix from the radio map (POST /v1/maps/{id}/localize, say), the filter's measurement. A
// scan ranged on transmitters also carries the ranging fix, whose covariance is kalman_ranging's
// R; any other fix's R comes from its accuracy_m.
struct RadioFix : Fix {
    RadioFix() = default;
    explicit RadioFix(const Fix& f) : Fix(f) {}  // a posted, matched or stored fix: no ranging, no readings

    std::optional<ranging::Fix> ranged;
    // ekf_ranging: the scan's readings of known transmitters (anchor ids as in FloorAnchors),
    // the filter's measurements; the position above only starts (or moves to another floor) it.
    std::vector<fusion::AnchorReading> readings;
    // ekf_ranging: a scan that could not be ranged on its own (fewer than three known
    // transmitters heard, or no fix from them): no position, only readings, which the running
    // filter takes; before it runs, the request is refused with this error (code, message).
    std::optional<std::pair<std::string, std::string>> unplaced;
};

// ekf_ranging's anchors: each floor's known transmitters.
struct FloorAnchors {
    std::map<std::int64_t, std::vector<fusion::RangingAnchor>> by_floor;
};

// A floor of the building the barometer tells apart: its id, elevation_m and whether it has a
// radio map (a floor without one is never a radio fix's floor: fusion::FloorLevel::radio).
struct BaroLevel {
    std::int64_t floor_id = 0;
    double elevation_m = 0;
    bool radio = true;
};

// Stairs or a lift between two floors: where it stands on the floor left and on the floor reached.
struct Crossing {
    Point from, to;
};

// A request ThinFusion cannot fuse, with the API error code it answers with.
struct CannotFuse : std::invalid_argument {
    CannotFuse(std::string c, const std::string& message) : std::invalid_argument(message), code(std::move(c)) {}
    std::string code;
};

// One track's filter.
class ThinFusion {
public:
    // seed: the filter's random seed (the track's id), the same at every restart.
    // options: the Kalman methods' noise (tracks/fusion_options.hpp), ignored by the others.
    explicit ThinFusion(FusionMethod method = FusionMethod::walk_pf, std::uint64_t seed = 1, const FusionOptions& options = {});

    // Runs the pressure samples, steps, radio fixes and GNSS fixes in time order
    // (fusion::time_order, kFixesFirst: pressure, then a radio fix, then a GNSS fix, then a step
    // of equal t) and answers one fused fix per step and radio fix, one per GNSS fix the filter
    // takes (not one thinned out, gated out or on a floor without a georeference), and one per
    // pressure sample that moves the track to another floor.
    // Steps and fixes at or before the last t an earlier call ran are skipped (no fix for them):
    // a client retrying a request whose answer it lost must not move the filter twice; pressure
    // samples at or before the last one run are skipped likewise. `walkable_of` gives a floor's
    // Walkable (nullptr when it has no plan: walk_pf walks freely, particle throws
    // std::invalid_argument). `floors` answers `levels(floor_id)`, the floors of that floor's
    // building that have an elevation (std::vector<BaroLevel>), asked once, at the first pressure
    // sample on that building, `crossing(from, to, at)`, the stairs or lift nearest `at` on
    // floor `from` that leads to floor `to` (std::optional<Crossing>), asked at a floor change,
    // and `georeference(floor_id)` (std::shared_ptr<const geo::FloorToEarth>, null: none), asked
    // at each GNSS fix the interval lets through.
    // Steps before any radio fix, with no filter yet, throw std::invalid_argument: the filter
    // starts at a fix; pressure and GNSS before it are not used.
    template <typename WalkableOf, typename Floors>
    std::vector<Fix> run(const std::vector<Step>& steps, const std::vector<RadioFix>& radio, const std::vector<Pressure>& pressure,
                         const std::vector<Gnss>& gnss, WalkableOf&& walkable_of, Floors&& floors);
    // Steps and radio fixes alone (no barometer).
    template <typename WalkableOf>
    std::vector<Fix> run(const std::vector<Step>& steps, const std::vector<RadioFix>& radio, WalkableOf&& walkable_of) {
        struct NoBarometer {
            std::vector<BaroLevel> levels(std::int64_t) const { return {}; }
            std::optional<Crossing> crossing(std::int64_t, std::int64_t, Point) const { return std::nullopt; }
            std::shared_ptr<const geo::FloorToEarth> georeference(std::int64_t) const { return nullptr; }
        };
        return run(steps, radio, {}, {}, walkable_of, NoBarometer{});
    }

    bool started() const { return filter_.has_value() || walk_.has_value() || kalman_.has_value() || ekf_.has_value(); }
    // ekf_ranging's anchors, read by the caller from the map's transmitters for each request:
    // a filter (re)started takes its floor's; a running one keeps those it started with.
    void set_anchors(std::shared_ptr<const FloorAnchors> anchors) { anchors_ = std::move(anchors); }
    // The latest t this filter has run (nullopt before its first input).
    std::optional<double> done_t() const { return done_t_; }
    // Where the filter is now, as a fused fix at done_t() (nullopt before it started).
    std::optional<Fix> estimate() const {
        if (!started() || !done_t_) return std::nullopt;
        return fused(*done_t_, heading_deg_);
    }
    // walk_pf: what the track's scans so far taught (tracks/scan_memory.hpp): the phone's RSS
    // offset, which the caller adds to each new scan before localizing it and then teaches with
    // the answer, and when each beacon last counted (only a scan after done_t() teaches: a
    // retried one taught it already). Copied with the filter, so a refused request teaches nothing.
    ScanMemory& scan_memory() { return scan_memory_; }
    const ScanMemory& scan_memory() const { return scan_memory_; }
    // Bytes this track's filter holds (not the floor's plan, which the floor's tracks share).
    std::size_t memory_bytes() const;
    // Starts the filter at a fix the track already stored (its latest), as if it were a radio
    // fix, and counts inputs up to its t as run: for a track whose filter this server does not
    // hold (a restart, or a request that reached another server sharing the database).
    // bearing_deg: the stored fix's floor's georeferenced bearing (nullopt: none), as in run().
    template <typename WalkableOf>
    void resume(const Fix& stored, WalkableOf&& walkable_of, std::optional<double> bearing_deg = std::nullopt) {
        std::shared_ptr<const fusion::Walkable> w = walkable_of(stored.floor_id);
        start(w.get(), RadioFix(stored), true, bearing_deg);
        heading_deg_ = stored.heading_deg;
        done_t_ = stored.t;
    }

private:
    Fix fused(double t, std::optional<double> heading_deg) const;
    // resumed: `r` is a fused fix the track stored, whose accuracy_m is the filter's own σ then.
    // bearing_deg: the floor's georeferenced bearing (walk_pf reads the steps' headings as
    // compass azimuths on it), nullopt when the floor has no georeference.
    void start(const fusion::Walkable* w, const RadioFix& r, bool resumed = false, std::optional<double> bearing_deg = std::nullopt);
    // The barometer's floor when it names one other than the filter's: the filter moves there,
    // through the stairs or lift `floors` gives (walk_pf keeps its cloud; the others restart at
    // their estimate). True when it moved.
    template <typename WalkableOf, typename Floors>
    bool follow_baro(double t, WalkableOf&& walkable_of, Floors&& floors);
    // A GNSS fix past the interval, on a floor with a georeference, as a position measurement
    // (gated for the Kalman methods). True when the filter took it.
    template <typename Floors>
    bool take_gnss(const Gnss& g, Floors&& floors);
    bool gnss_update(Point at, double sigma_m);
    // The index in baro_ids_ of a floor (nullopt: not one of the barometer's).
    std::optional<int> baro_index(std::int64_t floor_id) const;
    // The Kalman filter's R for a radio fix (client-lib's ranging_measurement_noise, the fix's
    // accuracy_m as an isotropic covariance when it was not ranged).
    Eigen::Matrix2d kalman_r(const RadioFix& r) const;

    FusionMethod method_;
    fusion::ParticleConfig config_;
    FusionOptions options_;  // walk_pf's, read at each (re)start: the floor's georeference decides too
    std::optional<fusion::ParticleFilter> filter_;  // copyable: a request runs on a copy
    std::optional<fusion::WalkFilter> walk_;        // one of the three, by method_
    fusion::RangingKalmanConfig kalman_config_;
    std::optional<fusion::KalmanFilter> kalman_;
    fusion::RangingEkfConfig ekf_config_;
    std::optional<fusion::RangingEkf> ekf_;
    std::shared_ptr<const FloorAnchors> anchors_;
    std::int64_t floor_id_ = 0;
    std::optional<double> heading_deg_;  // the last step's as sent (resumed: the stored fix's), uncorrected
    std::optional<double> done_t_;  // the latest t run so far
    // The barometric floor, once a pressure sample came on a building it can tell floors of:
    // BaroFloor's floors are indices into baro_ids_.
    std::optional<fusion::BaroFloor> baro_;
    std::vector<std::int64_t> baro_ids_;
    std::int64_t baro_asked_floor_ = 0;         // the floor levels_of was last asked for (0: never)
    std::optional<double> pressure_done_t_;   // the latest pressure sample run so far
    std::optional<double> gnss_t_;             // the latest GNSS fix the interval let through
    ScanMemory scan_memory_;
};

// walk_pf's configuration: WalkFilterConfig::real_walks(), known_rotation() of it when
// rotation_known (the floor's georeference gives the rotation: a step's heading is the
// compass's azimuth there, docs/tracks.md; or the options say the headings are the floor's),
// and the track's options over them.
fusion::WalkFilterConfig walk_config(const FusionOptions& options, std::uint64_t seed, bool rotation_known);

// The georeferenced bearing of a floor (`floors.georeference(floor_id)`, as ThinFusion::run's
// `floors` answers it), nullopt when it has none.
template <typename Floors>
std::optional<double> bearing_of(Floors&& floors, std::int64_t floor_id) {
    const std::shared_ptr<const geo::FloorToEarth> frame = floors.georeference(floor_id);
    return frame ? std::optional<double>(frame->georeference().bearing_deg) : std::nullopt;
}

// The radio fix's covariance: its accuracy as a 1-sigma radius.
Eigen::Matrix2d fix_covariance(double accuracy_m);

// A Kalman method's configuration: its defaults with the track's options over them.
fusion::RangingKalmanConfig kalman_config(FusionMethod method, const FusionOptions& options);
// ekf_ranging's: fusion::RangingEkfConfig's defaults with the track's options over them.
fusion::RangingEkfConfig ekf_config(const FusionOptions& options);

template <typename WalkableOf, typename Floors>
bool ThinFusion::follow_baro(double t, WalkableOf&& walkable_of, Floors&& floors) {
    const std::optional<int> b = baro_ ? baro_->floor() : std::nullopt;
    if (!b || baro_ids_[static_cast<std::size_t>(*b)] == floor_id_) return false;
    const std::int64_t to = baro_ids_[static_cast<std::size_t>(*b)];
    RadioFix here(fused(t, heading_deg_));
    Point shift{0.0, 0.0};
    if (const std::optional<Crossing> c = floors.crossing(floor_id_, to, Point{here.x, here.y})) shift = {c->to.x - c->from.x, c->to.y - c->from.y};
    std::shared_ptr<const fusion::Walkable> w = walkable_of(to);
    if (walk_) {
        walk_->change_floor(w ? std::optional<fusion::Walkable>(*w) : std::nullopt, shift);
        floor_id_ = to;
    } else {
        here.floor_id = to;
        here.x += shift.x;
        here.y += shift.y;
        start(w.get(), here, true);
    }
    return true;
}

template <typename Floors>
bool ThinFusion::take_gnss(const Gnss& g, Floors&& floors) {
    if (gnss_t_ && g.t - *gnss_t_ < fusion::kGnssMinIntervalS) return false;
    const std::shared_ptr<const geo::FloorToEarth> frame = floors.georeference(floor_id_);
    if (!frame) return false;
    // A fix the gate drops counts for the interval too, as in `locus eval ipin`'s trackers.
    gnss_t_ = g.t;
    return gnss_update(frame->to_floor({g.lat, g.lon}), std::max(g.accuracy_m, fusion::kGnssMinSigmaM));
}

template <typename WalkableOf, typename Floors>
std::vector<Fix> ThinFusion::run(const std::vector<Step>& steps, const std::vector<RadioFix>& radio, const std::vector<Pressure>& pressure,
                                 const std::vector<Gnss>& gnss, WalkableOf&& walkable_of, Floors&& floors) {
    std::vector<Fix> out;
    const std::optional<double> done = done_t_;
    const auto already_run = [&done](double t) { return done && t <= *done; };
    const std::vector<double> step_t = fusion::times_of(steps, &Step::t);
    const std::vector<double> pressure_t = fusion::times_of(pressure, &Pressure::t);
    // The fix stream holds the radio fixes (source 0) and the GNSS fixes (source 1), merged by
    // time (a radio fix first at equal t).
    const std::vector<double> radio_t = fusion::times_of(radio, &RadioFix::t), gnss_t = fusion::times_of(gnss, &Gnss::t);
    const fusion::MergedStream fixes = fusion::merge_sources({radio_t, gnss_t});
    for (const fusion::WalkEvent& e :
         fusion::time_order({.pressure = pressure_t, .step = step_t, .fix = fixes.t}, fusion::kFixesFirst)) {
        const double t = e.t_s;
        if (e.kind == fusion::EventKind::fix && fixes.source[e.index] == 1) {
            // GNSS alone does not begin a track: the filter starts at a radio fix.
            if (!started() || already_run(t) || !take_gnss(gnss[fixes.index[e.index]], floors)) continue;
            if (!done_t_ || t > *done_t_) done_t_ = t;
            out.push_back(fused(t, heading_deg_));
            continue;
        }
        if (e.kind == fusion::EventKind::pressure) {
            if (!started() || (pressure_done_t_ && t <= *pressure_done_t_)) continue;
            pressure_done_t_ = t;
            if (!baro_ && baro_asked_floor_ != floor_id_) {
                baro_asked_floor_ = floor_id_;
                std::vector<fusion::FloorLevel> levels;
                baro_ids_.clear();
                for (const BaroLevel& l : floors.levels(floor_id_)) {
                    levels.push_back({static_cast<int>(baro_ids_.size()), l.elevation_m, l.radio});
                    baro_ids_.push_back(l.floor_id);
                }
                if (levels.size() >= 2 && baro_index(floor_id_)) {
                    baro_.emplace(std::move(levels));
                    baro_->add_radio_vote(*baro_index(floor_id_));  // the fix the filter started at
                }
            }
            if (!baro_) continue;
            baro_->add_pressure(t, pressure[e.index].hpa);
            // A floor change is a fused fix only when it is the track's latest: fixes are stored in time order.
            if (follow_baro(t, walkable_of, floors) && (!done_t_ || t > *done_t_)) {
                done_t_ = t;
                out.push_back(fused(t, heading_deg_));
            }
            continue;
        }
        if (already_run(t)) continue;
        if (!done_t_ || t > *done_t_) done_t_ = t;
        if (e.kind == fusion::EventKind::fix) {
            const RadioFix& r = radio[fixes.index[e.index]];
            const Point at{r.x, r.y};
            bool ruled_out = false;
            if (const std::optional<int> vote = r.unplaced || !baro_ ? std::nullopt : baro_index(r.floor_id)) {
                baro_->add_radio_vote(*vote);
                const std::optional<int> b = baro_->floor();
                ruled_out = r.floor_id != floor_id_ && b && baro_ids_[static_cast<std::size_t>(*b)] != r.floor_id;
            }
            if (r.unplaced) {
                if (!ekf_) throw CannotFuse(r.unplaced->first, r.unplaced->second);
                ekf_->update(r.readings);
            } else if (ruled_out) {
                // The barometer rules the fix's floor out: its vote counted, its position does not.
                follow_baro(t, walkable_of, floors);
            } else if (!started() || r.floor_id != floor_id_) {
                std::shared_ptr<const fusion::Walkable> w = walkable_of(r.floor_id);
                start(w.get(), r, false, bearing_of(floors, r.floor_id));
                // Another building's floor: its barometer is asked for at the next pressure sample.
                if (baro_ && !baro_index(r.floor_id)) baro_.reset();
            } else if (ekf_) {
                if (r.readings.empty()) ekf_->update_position(at, fix_covariance(r.accuracy_m));
                else ekf_->update(r.readings);
            } else if (kalman_) {
                kalman_->update(at, kalman_r(r));
            } else if (walk_) {
                walk_->fix(at, fix_covariance(r.accuracy_m));
            } else {
                filter_->update(at, fix_covariance(r.accuracy_m));
            }
            out.push_back(fused(r.t, heading_deg_));
        } else {
            const Step& s = steps[e.index];
            if (!started()) throw std::invalid_argument("steps need a radio fix first (in this request or an earlier one): the filter starts there");
            const double heading_rad = s.heading_deg * 3.14159265358979323846 / 180.0;
            if (ekf_) ekf_->predict(pdr::step({0.0, 0.0}, s.length_m, heading_rad), s.t);
            else if (kalman_) kalman_->predict(pdr::step({0.0, 0.0}, s.length_m, heading_rad));
            else if (walk_) walk_->step(s.length_m, heading_rad);
            else filter_->predict(s.length_m, heading_rad);
            heading_deg_ = s.heading_deg;
            out.push_back(fused(s.t, heading_deg_));
        }
    }
    return out;
}

}  // namespace locus::tracks
