#pragma once
// A thin client's batch on its track (POST /v1/tracks/{id}/steps, docs/tracks.md): raw PDR
// steps, radio fixes and WiFi/BLE scans in, the track's filter's fused fixes out (and stored).
// Each scan becomes a radio fix: matched on the map's radio map (the particle filters), or
// ranged on the map's transmitters (the Kalman methods, ekf_ranging), whose readings of known
// transmitters are also ekf_ranging's measurements. On a walk_pf track each scan is shifted by
// the phone's RSS offset its filter has learnt from the track's earlier scans before it is
// matched, and then teaches the offset with the match (match::DeviceOffset, as `locus eval
// ipin`'s trackers do): phones of different makes read the same AP several dB apart. Its scans'
// strong readings of the map's BLE beacons (transmitters of type ble with a position) on the
// floor its running filter is on are also fixes at the beacon (locus/motion/fusion/beacon.hpp,
// as `locus eval ipin`'s trackers take them: never a track's start or a floor change); a scan of
// BLE readings alone that no RP shares an AP with is then no error. GNSS fixes
// are converted on the track's floor through its georeference, during the run. The localizers
// and georeferences are behind ScanLocalizer: the server's are map_scans.hpp's (the localize
// endpoint's matcher and ranging, the floors' georeference cache).
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "locus/geo/georeference.hpp"
#include "locus/geometry.hpp"
#include "locus/match/device_offset.hpp"
#include "locus/match/options.hpp"
#include "locus/ranging/trilateration.hpp"
#include "tracks/fusion.hpp"
#include "tracks/scan_area.hpp"
#include "tracks/service.hpp"
#include "tracks/steps_input.hpp"

namespace locus::tracks {

// The radio map's answer for a scan: its floor and position, and the positions of its k best
// candidates (their spread is the fix's accuracy); when asked with an offset, also the
// fingerprint it placed the scan at (the answer's RPs' mean RSS, AP by AP, over the scan's APs).
struct MatchedScan {
    std::int64_t floor_id = 0;
    Point at;
    std::vector<Point> spread;
    match::Fingerprint placed_at;
    bool fell_back = false;  // asked within `near`, matched on the whole map: no RP there shares an AP with it
};


// The map's transmitters' answer for a scan: a ranging fix on the floor heard most, or the
// ranging's refusal (fewer than three known transmitters heard, no fix) as {code, message};
// with the scan's readings of known transmitters when they were asked for.
struct RangedScan {
    std::vector<fusion::AnchorReading> readings;
    std::optional<std::pair<std::int64_t, ranging::Fix>> fix;  // floor id, fix
    std::pair<std::string, std::string> refused;               // when no fix
};

// A BLE transmitter of the map with a position: its floor and where it stands.
struct PlacedBeacon {
    std::int64_t floor_id = 0;
    Point at;
};

// How the track's map localizes a scan. One object serves one batch: it may read the map's
// transmitters or radio-map snapshot once and keep them for the batch's other scans. Each
// may throw CannotFuse for a scan it cannot localize (no reading, no match), which passes
// through.
class ScanLocalizer {
public:
    virtual ~ScanLocalizer() = default;
    // The map's known transmitters, each floor's, as ekf_ranging's anchors.
    virtual std::shared_ptr<const FloorAnchors> anchors(std::int64_t map_id) = 0;
    // With an offset (dB), each reading is read that much stronger, and the answer carries the
    // fingerprint the scan was placed at; without, the scan is matched as read. With `near`,
    // only RPs within its radius are candidates (match::Near), and when none of them shares an
    // AP with the scan it is matched on the whole map.
    virtual MatchedScan match(std::int64_t map_id, const TimedScan& scan, std::optional<double> rss_offset_db,
                              std::optional<match::Near> near = std::nullopt) = 0;
    // The map's beacon a reading is of (nullopt: not a BLE reading, or of no placed transmitter).
    virtual std::optional<PlacedBeacon> beacon(std::int64_t map_id, const Reading& reading) = 0;
    // A floor's georeference (null: none), for GNSS.
    virtual std::shared_ptr<const geo::FloorToEarth> georeference(std::int64_t floor_id) = 0;
    // By multilateration, else by the Kalman-fusion paper's trilateration.
    virtual RangedScan range(std::int64_t map_id, const TimedScan& scan, bool multilateration, bool with_readings) = 0;
};

// A radio fix (posted, or a scan's) on a floor that is not of the track's map.
struct ForeignFloor : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

struct StepsDone {
    Posted posted;
    std::vector<Fix> fused;       // the filter's fixes of this batch
    std::vector<Fix> scan_fixes;  // each scan's radio fix that has a position, in the scans' order
    std::vector<ScanArea> scan_areas;  // and where each was matched
    std::optional<double> rss_offset_db;  // walk_pf: the phone's offset learnt, after this batch
};

// Localizes the batch's scans, then fuses and stores it (Service::post_raw); nothing is
// written unless every part is good. Throws CannotFuse (code, message) for a batch the
// filter cannot take, a Kalman track's scan that cannot be ranged (ekf_ranging: only before
// its filter runs) included; ForeignFloor; and the Service's Refused. Costs the localizing of
// each scan, plus a read of the map's transmitters (cached) for a Kalman or live ekf_ranging
// track; a walk_pf track's scans are localized with the tracks' sessions lock held (the offset
// they are shifted by is the filter's), plus a walk over the postings of each scan's APs for
// the fingerprint it is taught with.
StepsDone post_steps(Service& svc, std::int64_t id, const StepsInput& in, ScanLocalizer& localizer);

}  // namespace locus::tracks
