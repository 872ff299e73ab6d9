#pragma once
// An IPIN 2023 logfile as `locus eval ipin` and `locus replay` take it (docs/ipin-import.md):
// its scans, steps, pressure, GNSS and beacon readings in the venue's frame, with its POSI
// landmarks as the truth; the map's floors as the server holds them; the server's answers to
// the walk's scans; and one of the trackers (tools/ipin_track.hpp) run over them.
//
// Cost: load_walk reads and parses the whole file (O(lines)); map_floors asks the server a few
// requests per floor; server_answers one localize request per scan (and one GET per RP the
// answers name, once, with the offset).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "locus/api/client.hpp"
#include "locus/geo/georeference.hpp"
#include "locus/match/device_offset.hpp"
#include "ipin_track.hpp"
#include "walk_survey.hpp"

namespace locus::tools::ipin {

struct LoadedWalk {
    std::string label, phone;
    Walk walk;
    std::vector<Fix> truth;  // POSI instants on the venue's floors
    std::vector<datasets::ipin::PressureSample> pressure;
    std::vector<ImuStep> steps;
    std::vector<GnssFix> gnss;
    std::vector<BleReading> ble;
    double end_s = 0.0;  // the last scan or POSI instant: the trackers' ticks run to here
};

// One logfile (CommandError naming the file and line when it does not parse). A file without
// POSI loads (no truth: `truth` and `walk.landmarks` empty).
LoadedWalk load_walk(const std::string& path);
// The files of DIR/trials matching any glob, sorted by name (CommandError when none).
std::vector<LoadedWalk> load_walks(const std::string& dir, const std::vector<std::string>& globs);

// Where each scan of a walk is, by the walking survey; nullopt where it is not placed.
std::vector<std::optional<Fix>> scan_truth(const Walk& w);

// The map's floors as the server holds them: level, the floor's own frame (to bring its
// answers into the venue's one frame through the Earth) and, for the barometer, its elevation.
struct MapFloors {
    struct Floor {
        int level = 0;
        std::optional<geo::FloorToEarth> frame;
    };
    std::map<long long, Floor> by_id;
    std::vector<fusion::FloorLevel> baro;
    std::vector<Beacon> beacons;  // the floors' BLE transmitters, in the venue's frame
};

// The map's floors (CommandError for a map without one); with want_baro, their barometric levels.
MapFloors map_floors(api::Client& client, std::int64_t map, bool want_baro);

// The RPs' fingerprints (mean RSS by AP), read from the server once each.
class RpFingerprints {
public:
    explicit RpFingerprints(api::Client& client) : client_(client) {}
    // The mean of the RPs' means, AP by AP (over the RPs that hear it).
    match::Fingerprint of(const std::vector<long long>& rp_ids);

private:
    api::Client& client_;
    std::unordered_map<long long, match::Fingerprint> cache_;
};

// The server's answer to each scan of a walk, in the venue's frame; nullopt where it had none.
// With `offset`, each scan is sent with the phone's offset learnt from the scans before it
// (match::DeviceOffset, each answer's RPs the fingerprint it is compared with).
std::vector<std::optional<Fix>> server_answers(api::Client& client, std::int64_t map, const MapFloors& floors, const LoadedWalk& lw,
                                               match::DeviceOffset* offset = nullptr, RpFingerprints* fingerprints = nullptr);

// What a tracker run takes beyond the walk: the known start (the first POSI), GNSS, the beacons.
struct TrackerInputs {
    bool known_start = false;
    bool gnss = true;
    bool ble = true;
};

// A tracker over the walk with `answers` as its WiFi fixes, the map's floors for the barometer
// and its beacons: its estimates every 0.5 s (tools/ipin_track.hpp).
std::vector<Fix> run_tracker(Tracker tracker, const LoadedWalk& lw, const std::vector<std::optional<Fix>>& answers,
                             const MapFloors& floors, const TrackerInputs& inputs);

}  // namespace locus::tools::ipin
