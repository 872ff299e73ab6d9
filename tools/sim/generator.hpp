#pragma once
// The seeded walking simulator (SPEC §7, issue 5): a person walks the scenario's path with
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
    int survey_scans = 30;         // per RP (seed default)
    // Per-person gait (drawn per seed around these).
    double step_length_m = 0.70;
    double step_length_person_sigma = 0.05;  // spread of the person's mean step length
    double step_length_sigma = 0.04;         // relative step-to-step spread
    double step_frequency_hz = 1.8;
    // Vertical bounce of this person's steps (peak-to-peak, m/s², phone in hand): log-normal
    // around this, independent of their step length, so the PDR's Weinberg length is off by
    // a few % per person, as an uncalibrated K is.
    double bounce_p2p = 3.6;
    double bounce_log_sigma = 0.2;
    // The phone is never held exactly along the walking direction: a per-walk yaw offset.
    double misalignment_sigma_rad = 0.12;  // ≈ 7°
    // Sensors.
    double acc_noise = 0.08;        // m/s² per sample
    double acc_bias_sigma = 0.05;   // m/s² per axis, per walk
    double gyro_noise = 0.01;       // rad/s per sample
    double gyro_bias_sigma = 0.004; // rad/s per axis, per walk (≈ 0.23°/s)
    double mag_noise = 0.6;         // µT per sample
    double device_offset_sigma_db = 2.0;  // online phone vs survey phone RSS offset
};

Walk simulate(const Scenario& scenario, std::uint64_t seed, const SimConfig& config = {});

}  // namespace locus::sim
