#pragma once
// The glue of `locus survey walk` and `locus import ipin` around the core's walking survey
// (locus/survey/walk.hpp): landmarks from a small CSV or from a GetSensorData logfile's POSI
// lines (lat/lon turned into a floor's frame by the caller), and the RP jobs of one walk for
// the uploader (survey_upload.hpp). docs/survey.md "Walking surveys" describes the storage.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "datasets/ipin_log.hpp"
#include "datasets/walk_files.hpp"
#include "locus/survey/walk.hpp"
#include "survey_upload.hpp"

namespace locus::tools {

// The log's POSI lines as landmarks, each through `to_floor(floor, lat, lon)`, which answers
// the floor-frame position or nullopt when that floor is not mapped (the landmark is then
// dropped: the walk has a gap there, treated as a floor change). `dropped` counts them.
using ToFloor = std::function<std::optional<Point>(int floor, double lat, double lon)>;
std::vector<survey::Landmark> landmarks_of_posi(const datasets::ipin::Log& log, const ToFloor& to_floor,
                                                std::size_t& dropped);

// One walk to upload: its scans (WiFi, in time order) and its landmarks.
struct Walk {
    std::string source;   // file named in messages
    std::string stem;     // names its RPs: "<stem> <cell>m #<k> <first 8 hex digits of content>"
    std::string content;  // content fingerprint of the file(s): makes the upload ids
    std::vector<survey::Landmark> landmarks;
    std::vector<double> scan_times;
    std::vector<Scan> scans;
};

// The walk's scans of a logfile (to_scan of each WIFI scan; scans left empty dropped).
void add_wifi_scans(const datasets::ipin::Log& log, Walk& walk);

// What became of one walk's scans.
struct WalkCounts {
    std::size_t scans = 0, placed = 0, before_first = 0, after_last = 0, floor_change = 0, unmapped_floor = 0;
    std::size_t rps = 0;
    std::map<int, std::size_t> rps_per_floor, scans_per_floor;
    nlohmann::json to_json() const;
};

// RP jobs of one walk: placed scans binned along the path (cell_m, 0: one RP per scan) into
// the radio map of their floor (`radiomap_of_floor`; scans on another floor are counted as
// unmapped_floor). Each RP's upload id is "walk-<content>-<cell>": re-running merges nothing
// twice. Throws std::invalid_argument from the core (landmarks out of time order).
std::vector<RpJob> walk_jobs(const Walk& walk, const std::map<int, std::int64_t>& radiomap_of_floor, double cell_m,
                             WalkCounts& counts);

// A cell as RP names and upload ids spell it: 0, 2, 2.5.
std::string cell_text(double cell_m);

}  // namespace locus::tools
