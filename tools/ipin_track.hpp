#pragma once
// The trackers of `locus eval ipin` (docs/ipin-import.md, "The trackers"): a walk's own IMU
// (steps from ACCE, their azimuth from the rotation vector) fused with the server's WiFi answers
// and the barometer, causally, one estimate every 0.5 s from the file's start (the competition's
// 2 Hz). Every event reaches the filters through fusion::run_walk in time order (pressure, step,
// answer, tick at equal times), so an estimate at t uses only what was stamped at or before t:
// cutting a walk at T leaves every estimate before T as it was.
//  - pdr: dead reckoning from the start; each step's compass azimuth turned into the venue's
//    frame by the rotation (and mirror) learnt so far from the WiFi answers
//    (fusion::HeadingAlignment), its length scaled by the scale learnt with it.
//  - walk_pf: fusion::WalkFilter (no plan: free moves), which learns the compass rotation and the
//    step scale itself, leaning on HeadingAlignment's rotation as a hint.
// Floors: fusion::BaroFloor, the pressure with each answer's floor as a radio vote (and the start
// floor, when known). Without a known start a tracker begins at the first answer; with one
// (the competition gave its walks' first landmark) it stands there until the landmark's time
// (the calibration minute is spent on it) and walks from then on.
//
// Cost per walk: log_steps O(ACCE samples · log AHRS samples); track O(events) for pdr and
// O(events · particles) for walk_pf (2000 particles: a few ms per walk).
#include <optional>
#include <span>
#include <vector>

#include "datasets/ipin_log.hpp"
#include "ipin_eval.hpp"
#include "locus/motion/fusion/baro_floor.hpp"
#include "locus/motion/fusion/walk_filter.hpp"

namespace locus::tools::ipin {

// A detected step, in the phone's compass frame.
struct ImuStep {
    double t_s = 0.0;          // AppTimestamp when the detector confirmed it (what the phone knows then)
    double length_m = 0.0;     // Weinberg
    double azimuth_rad = 0.0;  // clockwise from (magnetic) north, the rotation vector's at the step's own time
};

// Every step of the log's ACCE (sensor clock moved onto the App clock), in confirmation order.
// No AHRS sample: no step (the azimuth is unknown).
std::vector<ImuStep> log_steps(const datasets::ipin::Log& log);

enum class Tracker { pdr, walk_pf };

struct TrackerConfig {
    fusion::WalkFilterConfig walk_filter = fusion::WalkFilterConfig::real_walks();
    double answer_sigma_m = 3.0;  // σ of a WiFi answer for the filters (the walk filter takes at least its own)
    double tick_s = 0.5;          // the competition's 2 Hz
    // Answers the rotation must have been fitted on before pdr and walk_pf lean on it.
    int alignment_pairs = 3;
};

struct TrackInput {
    std::span<const ImuStep> steps;
    std::span<const datasets::ipin::PressureSample> pressure;
    std::span<const double> scan_times;                // every scan's time, in order
    std::span<const std::optional<Fix>> answers;       // the server's answer per scan (nullopt: none)
    double end_s = 0.0;                                // ticks run from 0 to here
    std::optional<Fix> start;                          // the known start (--known-start)
};

// The tracker's estimates at its ticks (from the first tick at which it has a position), in
// time order, venue frame. `floors`: the map's floors for BaroFloor (may be empty: then the
// floor is the last answer's, or the start's).
std::vector<Fix> track(Tracker tracker, const TrackInput& in, const std::vector<fusion::FloorLevel>& floors,
                       const TrackerConfig& config = {});

}  // namespace locus::tools::ipin
