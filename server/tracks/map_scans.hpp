#pragma once
// A thin client's WiFi/BLE scans on a track (POST /v1/tracks/{id}/steps, `scans`), localized
// on the track's map as POST /v1/maps/{id}/localize answers them: by the radio map's matcher
// (the localize service's index, with the radio map's stored defaults, as a request naming no
// algorithm), or by trilateration or multilateration on the map's transmitters
// (transmitters/ranging_scan.hpp, through the floors' transmitter cache). thin_client.hpp
// turns the answers into the track filter's radio fixes. A floor's georeference, for GNSS, is
// the floors' georeference cache's.
#include <cstdint>
#include <memory>
#include <optional>

#include "floors/floor_geo.hpp"
#include "localize/service.hpp"
#include "store/store.hpp"
#include "tracks/thin_client.hpp"
#include "transmitters/ranging_scan.hpp"
#include "transmitters/transmitter_cache.hpp"

namespace locus::tracks {

// What a track's scans are localized with: the server's one of each, shared by every request.
struct MapSources {
    store::Store& store;
    transmitters::TransmitterCache& transmitters;
    localize::Service& localizer;
    floors::FloorGeoCache& geo;
};

// One object per request: the map's transmitters and radio-map snapshot are read once, at the
// first scan that needs them.
class MapScans : public ScanLocalizer {
public:
    explicit MapScans(const MapSources& sources) : sources_(sources) {}

    std::shared_ptr<const FloorAnchors> anchors(std::int64_t map_id) override;
    // Throws CannotFuse invalid_field for a scan with no reading, no_match when no RP of the map
    // shares an AP with it (naming the scan). With an offset, the fingerprint costs a walk over
    // the postings of the scan's APs.
    MatchedScan match(std::int64_t map_id, const TimedScan& scan, std::optional<double> rss_offset_db,
                      std::optional<match::Near> near = std::nullopt) override;
    // Through the map's known transmitters (read once for the batch).
    std::optional<PlacedBeacon> beacon(std::int64_t map_id, const Reading& reading) override;
    std::shared_ptr<const geo::FloorToEarth> georeference(std::int64_t floor_id) override { return sources_.geo.of_floor(floor_id); }
    // A ranging refusal (too_few_transmitters, no_fix) is answered, not thrown, its message
    // naming the scan; a scan with no reading throws CannotFuse invalid_field.
    RangedScan range(std::int64_t map_id, const TimedScan& scan, bool multilateration, bool with_readings) override;

private:
    const transmitters::KnownTransmitters& known(std::int64_t map_id);

    MapSources sources_;
    std::optional<transmitters::KnownTransmitters> known_;
    std::shared_ptr<const localize::Snapshot> snapshot_;
};

// A thin client's batch on track `id`, its scans localized on the track's map: post_steps with
// a MapScans of `sources`. What POST /v1/tracks/{id}/steps runs, and its errors.
StepsDone post_steps(Service& svc, std::int64_t id, const StepsInput& in, const MapSources& sources);

}  // namespace locus::tracks
