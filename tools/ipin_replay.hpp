#pragma once
// `locus replay LOGFILE --map ID`: one GetSensorData/IPIN logfile through the real pipeline, as
// `locus replay` runs a walk file (docs/ipin-import.md, "Replaying a logfile"). The map, not one
// radio map: the walk may change floors, and every floor of the map is asked.
//  - walk_pf (the default), kalman, pdr: `locus eval ipin`'s trackers (tools/ipin_track.hpp) on
//    the log's IMU, the server's answers to its scans (sent with the phone's offset learnt
//    online), its barometer, GNSS and the map's beacons;
//  - wifi: the server's answers alone;
//  - thin: the log posted as a thin client posts it to a live track on the map, one request per
//    WiFi scan (the steps, pressure and GNSS since the last, then the scan:
//    POST /v1/tracks/{id}/steps), the server's filter (docs/tracks.md) answering the fixes; the
//    track opened as a phone opens it (no fusion_options: the server's defaults, headings as the
//    compass reads them, from north), or with the options given.
// The estimates are printed with their floor level, position in the venue's frame and WGS84;
// when the log has POSI landmarks they are scored as the competition scores them
// (tools/ipin_eval.hpp). A log without POSI replays (no score).
//
// Cost: the log read once; one localize request per scan (walk_pf, kalman, pdr, wifi) or one
// /steps request per scan (thin); the trackers a few ms per walk.
#include <cstdint>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "locus/api/client.hpp"

namespace locus::tools::ipin {

struct ReplayOptions {
    std::string file;
    std::int64_t map = 0;
    std::string rule = "walk_pf";  // walk_pf, kalman, pdr, wifi or thin
    bool known_start = false;      // the first POSI landmark given (a fix, for thin)
    bool gnss = true;
    bool ble = true;
    bool offset = true;            // the trackers' phone offset (thin: the server learns its own)
    // thin: the track's fusion_options as given (a JSON object, the server checks each); empty:
    // none, the server's defaults.
    std::string fusion_options;
};

// The replay's JSON: {file, format: "ipin", map, rule, phone, known_start, landmarks,
// estimates: [{t, floor, x, y, lat, lon}], score?: {p75_m, mean_m, floor_hit_rate, n, ...}}
// (thin also: track {id, token}, requests, refused_scans, dropped_steps, rss_offset_db). CommandError for a file that does
// not parse (naming its line), a map without floors, or an unknown rule; api errors pass.
nlohmann::json replay_log(api::Client& client, const ReplayOptions& options, std::ostream& log);

}  // namespace locus::tools::ipin
