#pragma once
// A thin client's WiFi/BLE scans on a track (POST /v1/tracks/{id}/steps, `scans`), localized
// on the track's map as POST /v1/maps/{id}/localize answers them: by the radio map's matcher
// (the localize service's index, the radio map's stored defaults: a request naming no
// algorithm), or by trilateration or multilateration on the map's transmitters (through the
// ranging localize's transmitter cache). tracks/thin_client.hpp turns the answers into the
// track filter's radio fixes. One object per request: the map's transmitters and snapshot are
// read once, at the first scan that needs them. A floor's georeference, for GNSS, is the
// floors' georeference cache's.
// Eigen first: cpp-httplib pulls in <resolv.h>, whose `_res` macro breaks Eigen.
#include "tracks/thin_client.hpp"

#include <cstdint>
#include <memory>
#include <optional>

#include "http/localize/ranging_localize.hpp"
#include "http/plans/floor_geo.hpp"
#include "http/transmitters/transmitter_cache.hpp"
#include "localize/service.hpp"
#include "store/store.hpp"

namespace locus::http {

class MapScans : public tracks::ScanLocalizer {
public:
    MapScans(store::Store& store, TransmitterCache& transmitters, localize::Service& localizer, FloorGeoCache& geo)
        : store_(store), transmitters_(transmitters), localizer_(localizer), geo_(geo) {}

    std::shared_ptr<const tracks::FloorAnchors> anchors(std::int64_t map_id) override;
    // Throws ApiError 422 invalid_field for a scan with no reading, 422 no_match when no RP
    // of the map shares an AP with it (naming the scan). With an offset, the fingerprint costs a
    // walk over the postings of the scan's APs.
    tracks::MatchedScan match(std::int64_t map_id, const tracks::TimedScan& scan, std::optional<double> rss_offset_db) override;
    std::shared_ptr<const geo::FloorToEarth> georeference(std::int64_t floor_id) override { return geo_.of_floor(floor_id); }
    // A ranging refusal (422 too_few_transmitters, no_fix) is answered, not thrown, its message
    // naming the scan; a scan with no reading throws 422 invalid_field.
    tracks::RangedScan range(std::int64_t map_id, const tracks::TimedScan& scan, bool multilateration, bool with_readings) override;

private:
    const KnownTransmitters& known(std::int64_t map_id);

    store::Store& store_;
    TransmitterCache& transmitters_;
    localize::Service& localizer_;
    FloorGeoCache& geo_;
    std::optional<KnownTransmitters> known_;
    std::shared_ptr<const localize::Snapshot> snapshot_;
};

}  // namespace locus::http
