#pragma once
// The simulator's two test floors, after Traini 2017 §4.3.2 (DISI, University of Bologna): a
// 222.8 m² ground floor walked for ~26 m, and a 452.4 m² basement walked for 52 m whose
// magnetic field is bent by the iron structure and wrecked near the technical room. The
// real plans are not in the thesis; these layouts keep the areas, walk lengths and the
// anomaly, and put the RPs on the path as the thesis did. The environment (APs, shadowing,
// magnetic field) is fixed per scenario; the walk seed changes the person, the phone and
// every noise draw.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "locus/motion/fusion/walkable.hpp"
#include "locus/geometry.hpp"

namespace locus::sim {

struct AccessPoint {
    std::string bssid;
    Point at;
    double rss_1m_dbm = -40.0;  // received power at 1 m
};

// A local magnetic source (hardware in a technical room): adds a field of this strength
// pointing away from the source horizontally and down, fading as a Gaussian of the radius.
// A transmitter at a known position (the anchors of the Kalman-fusion paper,
// docs/spec.md §8 "Sources": BLE beacons and WiFi APs whose coordinates and model are given to
// the phone). `tx_power_dbm` and `exponent` are what the deployment was configured with (the
// paper: n = 2); the building's true exponent may differ (`true_exponent`), which is one of
// the paper's error sources.
struct Beacon {
    std::string type;  // "ble" or "wifi", as scans name them
    std::string id;
    Point at;
    double height_m = 2.5;  // mounted above the floor; the phone is at Scenario::phone_height_m
    double tx_power_dbm = -59.0;
    double exponent = 2.0;
    double true_exponent = 2.0;
};

struct MagneticSource {
    Point at;
    double strength_ut = 0.0;
    double radius_m = 1.0;
};

struct Scenario {
    std::string name;
    std::string description;
    fusion::Walkable map;
    std::vector<Point> path;  // the walk, a polyline through doors
    std::vector<Point> rps;   // reference points, on the path
    std::vector<AccessPoint> aps;

    // Radio (log-distance path loss with walls and static shadowing).
    double path_loss_exponent = 2.5;
    double wall_loss_db = 4.0;
    double shadowing_sigma_db = 4.0;    // static, spatially smooth, per AP
    double shadowing_scale_m = 4.0;     // correlation length of the shadowing
    double noise_sigma_db = 5.0;        // per reading
    double sensitivity_dbm = -92.0;     // weaker readings are not reported
    double miss_probability = 0.1;      // an audible AP is still missing from a scan

    // Magnetic field: Earth's field (µT, floor frame: x, y = local north, z up), bent by a
    // smooth random rotation of amplitude structure_deflection_rad (iron in the structure),
    // plus local sources.
    double earth_horizontal_ut = 23.0;
    double earth_vertical_ut = -41.0;
    double structure_deflection_rad = 0.0;
    double structure_scale_m = 6.0;
    double structure_norm_ripple = 0.0;  // relative |B| ripple of the structure field
    std::vector<MagneticSource> sources;
    double north_offset_deg = 0.0;

    // Anchors at known positions (only open_area has them): 1 Hz readings (SimConfig's beacon_*).
    std::vector<Beacon> beacons;
    double beacon_shadowing_sigma_db = 2.0;  // static, spatially smooth, per anchor (furniture, people)
    double beacon_shadowing_scale_m = 3.0;
    double beacon_sensitivity_dbm = -100.0;
    double phone_height_m = 1.2;

    std::uint64_t environment_seed = 0;

    double area_m2() const;
    double path_length_m() const;
};

// "open_area" was first published as "seed004": scenario() and default_config() still take
// that name (a deprecated alias); walks it writes are named "open_area".
inline constexpr const char* kOpenAreaAlias = "seed004";

const Scenario& scenario(const std::string& name);  // throws std::invalid_argument
std::span<const std::string> scenario_names();

// RPs every `spacing` metres along a polyline, both ends included.
std::vector<Point> points_along(const std::vector<Point>& path, double spacing_m);
Point point_at_arc(const std::vector<Point>& path, double s);

}  // namespace locus::sim
