#pragma once
// locus_sim (sim/): the walking simulator and the scoring of the fusion methods, a library so
// that `locus sim`, `locus replay` and the tests run one simulator, and one that never needs
// the server (it uses shared/ and client-lib/ only).
//
// A walk: what a phone records (IMU at a fixed rate, WiFi scans) plus, when known, the
// ground truth at every sample, and the survey scans taken at the RPs to build the radio
// map. Written and read by walk_io as JSON lines (docs/fusion.md describes the format), so
// `locus replay` can run a simulated or recorded walk against a real server.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "locus/motion/fusion/walkable.hpp"
#include "locus/motion/pdr/vec3.hpp"
#include "locus/radio_map.hpp"
#include "locus/ranging/path_loss.hpp"

namespace locus::sim {

struct ImuSample {
    double t_s = 0.0;
    pdr::Vec3 acc;   // m/s², gravity included, device frame (Android axes)
    pdr::Vec3 gyro;  // rad/s
    pdr::Vec3 mag;   // µT
    std::optional<Point> truth;
};

struct WifiScan {
    double t_s = 0.0;
    Scan readings;
    std::optional<Point> truth;
};

// A transmitter whose position and model the phone is given (the Kalman-fusion paper's anchors), as a
// floor's transmitter list would state it: `dz` is its height above the phone.
struct Anchor {
    std::string type;  // "ble" or "wifi"
    std::string id;
    ranging::Transmitter tx;
};

struct SurveyPoint {
    std::string name;
    Point at;
    std::vector<Scan> scans;
};

struct Walk {
    std::string scenario;   // empty for a recorded walk
    std::uint64_t seed = 0;
    double rate_hz = 50.0;
    Point start;
    double start_heading_rad = 0.0;
    double north_offset_deg = 0.0;
    // |B| of the undisturbed geomagnetic field here (a world magnetic model gives it from
    // the building's location), so the PDR can tell a disturbed field from the first second.
    std::optional<double> earth_field_ut;
    std::optional<fusion::Walkable> map;  // rooms and doors, when known
    std::vector<SurveyPoint> survey;
    std::vector<ImuSample> imu;
    std::vector<WifiScan> scans;
    // Anchors at known positions and their readings, one scan a second (each anchor's
    // advertisement or beacon frame heard at that instant); empty without anchors.
    std::vector<Anchor> anchors;
    std::vector<WifiScan> anchor_scans;

    bool has_truth() const;
    // Truth at time t, linearly interpolated between the IMU samples that carry it.
    std::optional<Point> truth_at(double t_s) const;
};

}  // namespace locus::sim
