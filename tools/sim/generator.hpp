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
    // Weinberg constant of this person relative to the PDR default (their bounce per metre
    // of step): relative spread, so the PDR's step length is off by a few % per person.
    double weinberg_k_sigma = 0.06;
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
