#pragma once
// The Kalman-fusion paper's comparison on a walk with anchors (Walk::anchors, the open_area
// scenario): the anchors' 1 Hz readings averaged per anchor over a window (the paper's 5 s), each
// window ranged by trilateration (the paper's method) and by multilateration, and four tracks
// scored as `locus sim` scores every method: trilateration, multilateration, the paper's Kalman
// filter (trilateration fixes, constant R and Q) and ours (multilateration fixes with their own
// covariance as R, Q growing with the distance walked).
#include <memory>
#include <string>
#include <vector>

#include "locus/motion/fusion/ranging_ekf.hpp"
#include "locus/motion/fusion/ranging_fix.hpp"
#include "locus/ranging/trilateration.hpp"
#include "sim/evaluate.hpp"

namespace locus::sim {

struct RangingEvalConfig {
    double window_s = 5.0;  // the Kalman-fusion paper: 5 s of readings averaged, one coordinate per window
    // Ours may range other windows (1–3 s: more, noisier fixes with less lag were worse on
    // the tuning walks than the paper's 5 s).
    double multilateration_window_s = 5.0;
    ranging::TrilaterationOptions trilateration;
    ranging::MultilaterationOptions multilateration;
    fusion::RangingKalmanConfig trilateration_kalman = fusion::trilateration_kalman_config();
    fusion::RangingKalmanConfig kalman = default_kalman();
    // The window's average describes the phone at the window's middle, not at its end: ours
    // moves the fix by the PDR steps of the last this-many seconds (the paper's does not).
    double kalman_fix_latency_s = 1.0;
    // Ours learns the phone's RSS offset against the anchors' configured power as it goes: the
    // mean residual of every earlier window's fit, subtracted from the next window's readings
    // (causal). A common offset is what a phone model adds to every anchor alike; on the
    // tuning walks 101..160 it took the filter's final error from 1.21 to 1.11 m.
    bool learn_offset = true;
    // The tightly coupled filter (ekf_ranging): every 1 Hz reading is its measurement.
    fusion::RangingEkfConfig ekf;

    // Ours, tuned on seeds 101..160 (docs/transmitters.md): fusion::ranging_kalman_config().
    static fusion::RangingKalmanConfig default_kalman();
};

struct RangingFixes {
    std::vector<Fix> trilateration, multilateration;
    // The raw material of ekf_ranging: the walk's anchors and its scans' readings, a scan each.
    std::vector<fusion::RangingAnchor> anchors;
    std::vector<std::vector<fusion::AnchorReading>> scans;
};

// One fix per window (window_s for trilateration, multilateration_window_s for
// multilateration) with at least three anchors heard (fewer: no fix, PDR carries on).
// A reading is matched to its anchor by id; readings of unknown ids are ignored.
RangingFixes run_ranging(const Walk& walk, const RangingEvalConfig& config);

// trilateration, multilateration, kalman_trilateration, kalman_ranging, ekf_ranging (the readings
// themselves as the measurements, fusion::RangingEkf). With a floor plan ours is
// map-matched as the WiFi Kalman filter is (a fix off the walkable floor snapped into it).
std::vector<NamedTrack> run_ranging_methods(const std::vector<PdrStep>& steps, const RangingFixes& fixes, Point start,
                                            const RangingEvalConfig& config,
                                            std::shared_ptr<const fusion::PlanWalkable> floor_plan = nullptr);

}  // namespace locus::sim
