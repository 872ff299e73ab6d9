#pragma once
// Walk files: JSON lines, one object per line, each with a "type":
//   header  (first line) format "locus-walk", version 1, scenario, seed, rate_hz, start [x,y],
//           start_heading_rad, north_offset_deg, optional earth_field_ut, optional floor {width, height,
//           rooms [{id, name, rects [[xmin,ymin,xmax,ymax]…]}], doors [[x1,y1,x2,y2]…]}
//   survey  rp, x, y, scans [{bssid: rss, …}, …]   (the RP scans that build the radio map)
//   imu     t, acc [x,y,z], gyro [x,y,z], mag [x,y,z], optional truth [x,y]
//   wifi    t, rss {bssid: rss, …}, optional truth [x,y]
// Times in seconds, monotonic; device axes as Android's. Unknown types and keys are ignored
// so the format can grow.
#include <iosfwd>
#include <string>

#include "sim/walk.hpp"

namespace locus::sim {

void write_walk(std::ostream& out, const Walk& walk);
Walk read_walk(std::istream& in);  // throws std::runtime_error with the line number
void save_walk(const std::string& path, const Walk& walk);
Walk load_walk(const std::string& path);

}  // namespace locus::sim
