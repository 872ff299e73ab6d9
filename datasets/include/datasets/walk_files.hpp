#pragma once
// The small CSV files of a walking survey (docs/survey.md "Walking surveys", docs/ipin-import.md):
// a landmarks file for loggers without POSI lines, and the IPIN 2023 competition's beacon
// positions. Pure text parsing, O(text); the first bad line throws std::runtime_error
// "FILE:LINE: message", nothing is skipped silently (blank lines aside).
#include <string>
#include <string_view>
#include <vector>

#include "locus/survey/walk.hpp"

namespace locus::datasets {

// A header `t,floor,x,y` (any column order, more columns ignored), then one landmark per line:
// time (s, the logger's AppTimestamp clock), floor number (as the radio-map mapping names
// floors, a whole number within ±1000), x, y (metres in that floor's frame). Lines must be in
// time order. At least one landmark.
std::vector<locus::survey::Landmark> parse_landmarks_csv(std::string_view text, const std::string& file);

// One row of IPIN 2023's supplementary/BLE_Locations.csv: `bleID,Lat,Lon,floor`
// ("BLE1",49.46…,11.11…,00).
struct IpinBeacon {
    std::string name;  // "BLE1"
    int number = 0;    // n of "BLEn", 1..255: MAC BE:AC:20:23:00:0n, major 1, minor n
    double lat = 0.0, lon = 0.0;
    int floor = 0;     // a whole number within ±1000
    long line = 0;
};
// Errors: a header other than bleID,Lat,Lon,floor, a wrong cell count, a name not BLE<n>, a
// latitude or longitude off the globe, a floor not a whole number, a name given twice, no header.
std::vector<IpinBeacon> parse_ipin_beacons(std::string_view text, const std::string& file);

}  // namespace locus::datasets
