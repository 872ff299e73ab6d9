#pragma once
// A scan ranged on the transmitters at known positions (the floors' transmitters), not on a
// radio map's RPs: what POST …/localize answers with "algorithm": "trilateration",
// "multilateration" or "proximity" (the nearest one: "you are at beacon X";
// http/localize/ranging_localize.hpp reads the body and writes the answer),
// and what a thin client's scans become on a track fused by a Kalman method
// (tracks/map_scans.hpp).
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "locus/match/query.hpp"
#include "locus/ranging/trilateration.hpp"
#include "store/store.hpp"
#include "transmitters/transmitter_cache.hpp"

namespace locus::transmitters {

struct RangingRequest {
    bool multilateration = false;  // else the Kalman-fusion paper's trilateration
    bool proximity = false;        // neither: the strongest known transmitter (nearest_transmitter)
    match::Query query;
    ranging::TrilaterationOptions trilateration;
    ranging::MultilaterationOptions multilateration_options;
    double phone_height = 1.2;  // m above the floor: a transmitter's z is measured against it
};

// A scan ranged on the floor that hears most of its known transmitters.
struct Ranged {
    std::int64_t floor_id = 0;
    ranging::Fix fix;
    std::size_t heard = 0;  // known transmitters of that floor the scan hears
};

// The transmitters a scan may hear, as ranging sees them (keyed "type|bssid"): every floor's
// of a map (map_scope) or the radio map's floor's. Read once for a batch of scans.
struct KnownTransmitter {
    std::int64_t floor_id = 0;
    ranging::Transmitter tx;
    std::int64_t id = 0;         // the transmitter's row
    std::string name;            // "" when it has none
};
// A transmitter's key in KnownTransmitters: "type|bssid", the bssid normalised.
std::string transmitter_key(std::string_view type, std::string_view bssid);
struct KnownTransmitters {
    bool map_scope = false;
    std::map<std::string, KnownTransmitter> by_key;
};
// NotFound for an unknown map or radio map. Costs a store read per floor the cache lacks.
KnownTransmitters known_transmitters(store::Store& store, TransmitterCache& cache, bool map_scope, std::int64_t id, double phone_height);

// The fix on the floor whose known transmitters the scan hears most. Throws Refused
// too_few_transmitters (with the count heard) when fewer than three are heard, no_fix when
// the method finds no position (every transmitter past the cutoff, or in a line). `known`
// must have been read with the request's phone_height.
Ranged range_scan(const KnownTransmitters& known, const RangingRequest& request);

// The known transmitter the scan hears strongest: where the phone most likely is near (a
// beacon at an entrance, a checkpoint), with the horizontal range its path-loss model gives
// for the reading. Throws Refused no_known_transmitter when the scan hears none. Costs a
// lookup per AP of the query.
struct Nearest {
    const KnownTransmitter* transmitter = nullptr;  // into `known`
    std::string type, bssid;
    double rss = 0.0;
    double range_m = 0.0;
    std::size_t heard = 0;  // known transmitters the scan hears, every floor
};
Nearest nearest_transmitter(const KnownTransmitters& known, const match::Query& query);

}  // namespace locus::transmitters
