#pragma once
// `locus replay LOGFILE --map ID`: one GetSensorData/IPIN logfile through the real pipeline, as
// `locus replay` runs a walk file (docs/ipin-import.md, "Replaying a logfile"). The map, not one
// radio map: the walk may change floors, and every floor of the map is asked.
//  - walk_pf (the default; `thin` is the same): the log posted as a thin client posts it to a
//    live track on the map, one request per WiFi scan (the steps, pressure, GNSS and BLE
//    readings since the last, then the scan: POST /v1/tracks/{id}/steps), the server's own
//    filter (docs/tracks.md) answering the fixes: what a phone gets. The track is opened as a
//    phone opens it (no fusion_options: the server's defaults, headings as the compass reads
//    them, from north), or with the options given.
//  - kalman, pdr: `locus eval ipin`'s baselines (tools/ipin_track.hpp) on the log's IMU, the
//    server's answers to its scans (sent with the phone's offset learnt online), its barometer,
//    GNSS and the map's beacons;
//  - wifi: the server's answers alone.
// The estimates are printed with their floor level, position in the venue's frame and WGS84;
// when the log has POSI landmarks they are scored as the competition scores them
// (tools/ipin_eval.hpp). A log without POSI replays (no score).
//
// Cost: the log read once; one /steps request per WiFi scan (walk_pf) or one localize request
// per scan (kalman, pdr, wifi); the baselines a few ms per walk.
#include <cstdint>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "ipin_walk.hpp"
#include "locus/api/client.hpp"

namespace locus::tools::ipin {

struct ReplayOptions {
    std::string file;
    std::int64_t map = 0;
    std::string rule = "walk_pf";  // walk_pf (= thin), kalman, pdr or wifi
    bool known_start = false;      // the first POSI landmark given (a fix of 0.5 m, for walk_pf)
    bool gnss = true;
    bool ble = true;
    bool offset = true;            // kalman and pdr: the phone's offset (walk_pf: the server learns its own)
    // walk_pf: the track's fusion_options as given (a JSON object, the server checks each); empty:
    // none, the server's defaults.
    std::string fusion_options;
};

// The replay's JSON: {file, format: "ipin", map, rule, phone, known_start, landmarks,
// estimates: [{t, floor, x, y, lat, lon}], score?: {p75_m, mean_m, floor_hit_rate, n, ...}}
// (walk_pf also: track {id, token}, requests, refused_scans, dropped_steps, rss_offset_db). CommandError for a file that
// does not parse (naming its line), a map without floors, or an unknown rule; api errors pass.
nlohmann::json replay_log(api::Client& client, const ReplayOptions& options, std::ostream& log);

// The walk on a live track of the map, as walk_pf replays it (`options`: map, known_start, gnss,
// ble, fusion_options): the server's fused fixes in the venue's frame, on the log's clock, in
// time order. `out` gets the track's {id, token}, requests, refused_scans, dropped_steps and
// rss_offset_db (and fusion_options when given); the track is closed at the end. With
// `scan_fixes`: per WiFi scan of the walk, its own fix as the server matched it (scan_fixes of
// its request, venue frame), none when refused.
std::vector<Fix> live_track(api::Client& client, const LoadedWalk& lw, const MapFloors& floors, const ReplayOptions& options,
                            nlohmann::json& out, std::ostream& log, std::vector<std::optional<Fix>>* scan_fixes = nullptr);

}  // namespace locus::tools::ipin
