#pragma once
// The seeded walking simulator (docs/spec.md §7.2): a person walks the scenario's path with
// the phone held flat in front, screen up, top pointing where they walk.
#include <cstdint>

#include "sim/scenario.hpp"
#include "sim/walk.hpp"

namespace locus::sim {

struct SimConfig {
    double rate_hz = 50.0;
    double stand_before_s = 2.0;   // still at the start: the compass settles
    double stand_after_s = 1.0;
    double scan_period_s = 3.0;    // one WiFi scan every this many seconds
    int survey_scans = 30;         // per RP (docs/spec.md §3.2)
    // Per-person gait (drawn per seed around these).
    double step_length_m = 0.70;
    // Spread of the person's mean step length, which the PDR's fixed Weinberg K does not
    // know: calibrated (seeds 101..120, docs/fusion.md) to Traini 2017's PDR distance errors on
    // the basement walk, +9.8 % and −15.0 % (57.12 and 44.19 m for 52 m).
    double step_length_person_sigma = 0.15;
    double step_length_sigma = 0.04;         // relative step-to-step spread
    double step_frequency_hz = 1.8;
    // Vertical bounce of this person's steps (peak-to-peak, m/s², phone in hand): log-normal
    // around this, independent of their step length, so the PDR's Weinberg length is off by
    // a few % per person, as an uncalibrated K is.
    double bounce_p2p = 3.6;
    double bounce_log_sigma = 0.2;
    // The phone is never held exactly along the walking direction: a per-walk yaw offset
    // (it also stands for the residual compass calibration error of the phone). Calibrated
    // to Traini 2017's ground-floor PDR final error, 3.80 and 4.38 m over 26 m.
    double misalignment_sigma_rad = 0.20;  // ≈ 11.5°
    // ...and the compass's rotation against the walking direction is not fixed either: on the
    // real PUTMC walks it wanders 80–370° within one walk, a random walk of 0.28 rad/√m
    // between consecutive scans (0.32 over four), `locus eval walks --reality`. Added to the
    // phone's yaw per metre walked, so gyroscope and magnetometer agree on it as they do on a
    // real phone whose fused azimuth drifts. 0 = the fixed offset alone (the simulator's first model).
    double heading_walk_rad_per_sqrt_m = 0.28;
    // Sensors.
    double acc_noise = 0.08;        // m/s² per sample
    double acc_bias_sigma = 0.05;   // m/s² per axis, per walk
    double gyro_noise = 0.01;       // rad/s per sample
    double gyro_bias_sigma = 0.004; // rad/s per axis, per walk (≈ 0.23°/s)
    double mag_noise = 0.6;         // µT per sample
    double device_offset_sigma_db = 4.0;  // online phone vs survey phone RSS offset
    // A scan sweeps the channels one after the other: each AP is heard at one instant of the
    // last scan_duration_s before the results arrive, so a walking scan mixes positions
    // (a dual-band scan takes 1.5–3 s on a phone). 0 = every AP heard where the results arrive.
    double scan_duration_s = 2.0;
    // The building on the walk's day is not the building of the survey day (people, doors,
    // furniture; Wu et al. 2015, AcMu): a per-walk smooth change of each AP's mean RSS over the
    // floor, this σ and correlation length; it also stands for the walker's own body
    // shadowing the phone. Online scans only. Calibrated so that Traini 2017's RSS matchers
    // (nn, bsbnn) miss by ~3 m on average, as they did there (docs/fusion.md).
    double survey_drift_sigma_db = 7.5;
    double survey_drift_scale_m = 4.0;
    // Anchors at known positions (Scenario::beacons): readings at this rate, each with this
    // much Gaussian noise (multipath, the body; the Kalman-fusion paper §3.2), plus this phone's offset
    // against the anchors' configured RSS at 1 m (drawn per walk).
    double beacon_rate_hz = 1.0;
    double beacon_noise_sigma_db = 4.0;
    double beacon_phone_offset_sigma_db = 2.0;
};

// The simulator's settings for a scenario: SimConfig's defaults, except open_area's walker and
// anchors, calibrated on walks 101..120 to the paper's own PDR and trilateration figures
// (2.38 and 2.77 m final error, docs/transmitters.md): a phone held steadily along the walk
// in an open room (little heading drift, a step length close to the PDR's).
SimConfig default_config(const std::string& scenario);

Walk simulate(const Scenario& scenario, std::uint64_t seed, const SimConfig& config = {});

}  // namespace locus::sim
