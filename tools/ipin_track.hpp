#pragma once
// The baseline trackers of `locus eval ipin` (docs/ipin-import.md, "The trackers"): a walk's own
// IMU (steps from ACCE, their azimuth from the rotation vector) fused with the server's WiFi
// answers, the barometer, GNSS and the map's BLE beacons, causally, one estimate every 0.5 s from
// the file's start (the competition's 2 Hz). The default, walk_pf, is not here: it is the
// server's own live track (tools/ipin_replay.hpp posts the walk to it), so that what the
// evaluation reports is what a phone gets. Every event reaches these filters through
// fusion::run_walk in time order (pressure, step, answer, tick at equal times), so an estimate
// at t uses only what was stamped at or before t: cutting a walk at T leaves every estimate
// before T as it was.
//  - pdr: dead reckoning from the start; each step's compass azimuth turned into the venue's
//    frame by the floor's georeferenced rotation, else the rotation (and mirror) learnt so far
//    from the WiFi answers (fusion::HeadingAlignment), its length scaled by the scale learnt
//    with it.
//  - kalman: fusion::KalmanFilter, the same steps as pdr as its control input, each answer a fix.
//  GNSS (unless --no-gnss): each fix a position measurement of σ its reported accuracy (at
//  least TrackerConfig::gnss_min_sigma_m) for kalman (gated), once it has begun; it names no
//  floor. pdr does not take it (its rotation is fitted on the WiFi answers).
//  BLE beacons (unless --no-ble): a reading of a beacon the map holds, at or above
//  TrackerConfig::ble_min_rss_dbm (-65), says the phone is near it, on its floor: a position
//  measurement at the beacon (σ ble_sigma_m) for kalman (gated), and a floor vote.
// Floors: fusion::BaroFloor, the pressure with each answer's floor as a radio vote (and the start
// floor, when known). Without a known start a tracker begins at the first answer; with one
// (the competition gave its walks' first landmark) it stands there until the landmark's time
// (the calibration minute is spent on it) and walks from then on.
//
// Cost per walk: log_steps O(ACCE samples · log AHRS samples); track O(events).
#include <optional>
#include <span>
#include <vector>

#include "datasets/ipin_log.hpp"
#include "ipin_eval.hpp"
#include "phone_steps.hpp"
#include "locus/motion/fusion/baro_floor.hpp"
#include "locus/motion/fusion/beacon.hpp"
#include "locus/motion/fusion/gnss.hpp"
#include "locus/motion/fusion/kalman.hpp"

namespace locus::tools::ipin {

// A detected step, in the phone's compass frame (AppTimestamp; the azimuth clockwise from
// magnetic north, the rotation vector's or the gyroscope's).
using ImuStep = PhoneStep;  // tools/phone_steps.hpp

// Every step of the log's ACCE (sensor clock moved onto the App clock), in confirmation order.
// No azimuth sample (AHRS, or GYRO with ACCE): no step.
enum class HeadingSource { rotation_vector, gyro };
// The rotation vector (the default): referenced to north, so the rotation to a georeferenced
// frame is known; the gyroscope's integrated turn has no reference and drifts with its bias
// (measured worse on the folds with the walk filter, docs/results.md).
std::vector<ImuStep> log_steps(const datasets::ipin::Log& log, HeadingSource source = HeadingSource::rotation_vector);

enum class Tracker { pdr, kalman };

struct TrackerConfig {
    // kalman: the position filter of `locus eval walks` (its per-metre step noise for real
    // compasses, tools/walk_eval.hpp), the answers as fixes of σ answer_sigma_m.
    fusion::KalmanConfig kalman = {.initial_sigma_m = 1.0, .step_sigma_floor_m = 0.05, .step_sigma_per_m = 4.0};
    double step_scale = 0.9;      // the steps' scale until the answers fit one
    double answer_sigma_m = 6.0;  // σ of a WiFi answer for kalman
    double tick_s = 0.5;          // the competition's 2 Hz
    // GNSS indoors (locus/motion/fusion/gnss.hpp, the settings the server's live tracks share):
    // a fix's σ is its accuracy, at least gnss_min_sigma_m; kalman drops a fix beyond gnss_gate
    // Mahalanobis units; one fix per gnss_min_interval_s at most.
    double gnss_min_sigma_m = fusion::kGnssMinSigmaM;
    double gnss_gate = fusion::kGnssGateChi2;
    double gnss_min_interval_s = fusion::kGnssMinIntervalS;
    // BLE: the settings the server's live tracks share (locus/motion/fusion/beacon.hpp).
    double ble_min_rss_dbm = fusion::kBeaconMinRssDbm;
    double ble_sigma_m = fusion::kBeaconSigmaM;
    double ble_min_interval_s = fusion::kBeaconMinIntervalS;
    // Answers the rotation (and the step scale) must have been fitted on before the trackers lean on them.
    int alignment_pairs = 3;
    // The compass's rotation to the venue's frame when it is known: a rotation-vector azimuth is
    // referenced to (magnetic) north, and a georeferenced floor's frame is north-up turned by its
    // bearing, so the rotation is known up to declination and the phone's bias. Then pdr and
    // kalman turn their steps by it instead of by the rotation learnt from the answers.
    std::optional<double> compass_offset_rad;
};

// A GNSS fix in the venue's frame: its time (AppTimestamp), where, and the receiver's own
// accuracy (m, its 68 % radius).
struct GnssFix {
    double t = 0.0;
    Point at;
    double accuracy_m = 0.0;
};

// The GNSS fixes of a log in the venue's frame: each fix once (the logger writes each twice),
// in time order, those without a positive accuracy left out.
template <typename ToFloor>
std::vector<GnssFix> log_gnss(const datasets::ipin::Log& log, ToFloor&& to_floor) {
    std::vector<GnssFix> out;
    std::optional<double> last_fix_s;
    for (const auto& g : log.gnss) {
        if (last_fix_s && g.sensor_s == *last_fix_s) continue;
        last_fix_s = g.sensor_s;
        if (!(g.accuracy_m > 0.0)) continue;
        out.push_back({g.app_s, to_floor(g.lat_deg, g.lon_deg), g.accuracy_m});
    }
    return out;
}

// A beacon the map holds, in the venue's frame.
struct Beacon {
    Bssid mac;
    int floor = 0;
    Point at;
};

// A beacon reading of a log (AppTimestamp, the normalised MAC, dBm).
struct BleReading {
    double t = 0.0;
    Bssid mac;
    double rss_dbm = 0.0;
};

std::vector<BleReading> log_ble(const datasets::ipin::Log& log);

// A beacon reading strong enough to place the phone: near `at`, on `floor`.
struct BeaconFix {
    double t = 0.0;
    int floor = 0;
    Point at;
};

// The readings (time order) of beacons in `beacons` at or above config.ble_min_rss_dbm, each
// beacon at most once per config.ble_min_interval_s. O(readings · beacons).
std::vector<BeaconFix> beacon_fixes(std::span<const BleReading> readings, std::span<const Beacon> beacons,
                                    const TrackerConfig& config);

struct TrackInput {
    std::span<const ImuStep> steps;
    std::span<const datasets::ipin::PressureSample> pressure;
    std::span<const double> scan_times;                // every scan's time, in order
    std::span<const std::optional<Fix>> answers;       // the server's answer per scan (nullopt: none)
    double end_s = 0.0;                                // ticks run from 0 to here
    std::optional<Fix> start;                          // the known start (--known-start)
    std::span<const GnssFix> gnss;                     // empty: without GNSS (--no-gnss)
    std::span<const BeaconFix> ble;                    // empty: without BLE (--no-ble)
};

// The tracker's estimates at its ticks (from the first tick at which it has a position), in
// time order, venue frame. `floors`: the map's floors for BaroFloor (may be empty: then the
// floor is the last answer's, or the start's).
std::vector<Fix> track(Tracker tracker, const TrackInput& in, const std::vector<fusion::FloorLevel>& floors,
                       const TrackerConfig& config = {});

}  // namespace locus::tools::ipin
