#pragma once
// locus_datasets (datasets/): the data set and file readers, a library apart from the CLI so that
// tests, benchmarks and fuzz targets read a file exactly as the commands do.
//
// Readers for the logs the `locus pdr` commands take. Here, not in client-lib/pdr, because
// client-lib does no I/O.
#include <string>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/motion/pdr/vec3.hpp"

namespace locus::datasets {

struct AccelSample {
    double t_s;
    double ax, ay, az;
};

// Oxford step-counter format (`timestamp_ns,accuracy,ax,ay,az`, no header) or a headered CSV
// whose header names t, ax, ay, az (seconds, m/s²; other columns ignored). Detected from the
// first line. Throws std::runtime_error with the line number on malformed input.
std::vector<AccelSample> read_accel_log(const std::string& path);

// IMU log for `pdr track` (docs/pdr.md): header `t,sensor,x,y,z`, then one sample per line,
// t in seconds (monotonic), sensor one of acc (m/s², gravity included), gyro (rad/s),
// mag (µT), step (platform step event; x, y, z ignored and may be empty). Lines starting
// with '#' are comments.
enum class ImuSensor { acc, gyro, mag, step };
struct ImuSample {
    double t_s;
    ImuSensor sensor;
    pdr::Vec3 v;
};
std::vector<ImuSample> read_imu_log(const std::string& path);

// A floor in the schema/demo_map.json shape: either a floor object itself or a whole map, in
// which case buildings[building].floors[floor] is used. Rectangles may be objects
// {xmin, ymin, xmax, ymax} or arrays [xmin, ymin, xmax, ymax]. north_offset_deg is returned apart.
FloorPlan read_floor_plan(const std::string& path, int building, int floor, double& north_offset_deg);

}  // namespace locus::datasets
