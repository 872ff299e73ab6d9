#pragma once
// locus_datasets (datasets/): the data set and file readers, a library apart from the CLI so that
// tests, benchmarks and fuzz targets read a file exactly as the commands do.
//
// Readers for other systems' survey data, without I/O:
// - FIND3 fingerprints (schollz/find3 `/data` export, JSON lines):
//   {"t": ms, "f": family, "d": device, "l": location label, "s": {"wifi": {bssid: rss}, "bluetooth": {...}}}
// - Anyplace rss-log lines (dmsl/anyplace): `timestamp_ms lat lon heading_deg bssid rss floor`,
//   '#' lines are comments.
// Bad lines are reported with their number and skipped.
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "datasets/survey_format.hpp"
#include "locus/geometry.hpp"
#include "locus/radio_map.hpp"

namespace locus::datasets::survey {

struct Find3Data {
    std::string family;                             // of the first line
    std::map<std::string, std::vector<Scan>> by_label;  // sorted by label
    std::vector<LineError> errors;
    std::size_t scans = 0, readings = 0;
};
Find3Data parse_find3(std::string_view text);

struct AnyplaceLine {
    long long timestamp = 0;
    double lat = 0.0, lon = 0.0;
    std::string bssid;
    double rss = 0.0;
    std::string floor;
};
struct AnyplaceData {
    std::vector<AnyplaceLine> lines;
    std::vector<LineError> errors;
};
AnyplaceData parse_anyplace(std::string_view text);

// Degrees to local metres around (lat0, lon0): x east, y north (equirectangular; the error
// over a building's few hundred metres is far below a metre).
Point project(double lat, double lon, double lat0, double lon0);

}  // namespace locus::datasets::survey
