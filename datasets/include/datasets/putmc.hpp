#pragma once
// Reader of the PUTMC data set (Nowicki & Skrzypczyński 2019; ../shared/data/README.md):
// a floor's survey (map/positions.map, map/wifi.map, map/scale.map) and phone walks
// (trajs/NAME/acc.map, orient.map, wifi.map, positions.map). Parsing only: every error is a
// std::runtime_error naming the file and line (truncated block, unsorted timestamp, NaN,
// a scan's point missing from positions.map), so a bad file is fixed, not guessed at.
#include <string>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/motion/pdr/vec3.hpp"
#include "locus/radio_map.hpp"

namespace locus::datasets::putmc {

struct AccSample {
    double t_s = 0.0;  // the file's nanoseconds as seconds (the phone's boot clock)
    pdr::Vec3 a;       // m/s², gravity included
};

// The phone's rotation vector (Android TYPE_ROTATION_VECTOR): device frame → east-north-up.
struct OrientSample {
    double t_s = 0.0;
    double qx = 0.0, qy = 0.0, qz = 0.0, qw = 1.0;
    double accuracy_rad = 0.0;
};

struct WifiScan {
    double t_s = -1.0;  // -1 in the survey (no time)
    int loc_id = 0;     // a point of the matching positions.map
    Scan readings;
    long line = 0;      // the block's header line, for messages
};

struct Position {
    int id = 0;
    Point at;  // metres, the plan image's frame (x right, y down)
};

struct Walk {
    std::string name;  // the directory's name, e.g. xperia_traj1
    std::vector<AccSample> acc;
    std::vector<OrientSample> orient;
    std::vector<WifiScan> scans;
    std::vector<Position> positions;
    Point truth_of(const WifiScan& s) const;  // the scan's ground-truth point
};

struct Survey {
    double px_per_m = 0.0;
    std::vector<Position> positions;
    std::vector<WifiScan> scans;  // one per point of positions.map
    Point at_of(int loc_id) const;  // throws std::out_of_range for an unknown id
};

// Parsers of one file's text; `file` names it in errors.
std::vector<AccSample> parse_acc(const std::string& text, const std::string& file);
std::vector<OrientSample> parse_orient(const std::string& text, const std::string& file);
// `timed`: walk scans (timestamps in ns, sorted); the survey's are -1.
std::vector<WifiScan> parse_wifi(const std::string& text, const std::string& file, bool timed);
std::vector<Position> parse_positions(const std::string& text, const std::string& file);
double parse_scale(const std::string& text, const std::string& file);

// A walk directory (trajs/NAME) and the survey directory (map/). Every scan's loc_id must
// name a line of positions.map.
Walk read_walk(const std::string& dir);
Survey read_survey(const std::string& map_dir);
// The walk directories under DIR/trajs (or DIR itself holding acc.map), sorted by name.
std::vector<std::string> walk_dirs(const std::string& dir);

// Azimuth of the phone's y axis (top edge), clockwise from magnetic north, radians in
// (−π, π]: Android's SensorManager.getOrientation()[0] of the rotation vector's matrix.
double android_azimuth(const OrientSample& q);

}  // namespace locus::datasets::putmc

namespace locus::datasets::putmc {

// PUTMC metres have y pointing down the plan image; a Locus floor's y points up (the image's
// bottom-left corner at the floor's origin, docs/spec.md §2.1). The floor's height is the
// image's height in metres, so a point keeps its place on the drawing.
inline Point to_floor(Point putmc, double floor_height_m) { return {putmc.x, floor_height_m - putmc.y}; }

}  // namespace locus::datasets::putmc
