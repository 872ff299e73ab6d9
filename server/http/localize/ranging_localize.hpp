#pragma once
// POST …/localize with "algorithm": "trilateration" or "multilateration": a position from the
// RSS of transmitters at known positions (the floor's transmitters), not from a radio map's
// RPs. Same endpoints and body as the fingerprint matchers; its own options.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "locus/match/query.hpp"
#include "locus/ranging/trilateration.hpp"
#include "http/transmitters/transmitter_cache.hpp"
#include "store/store.hpp"

namespace locus::http {

struct RangingRequest {
    bool multilateration = false;  // else the Kalman-fusion paper's trilateration
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

// nullopt when the body names no ranging algorithm (the fingerprint parser then reads it).
// Throws ApiError for a bad body that does name one.
std::optional<RangingRequest> parse_ranging_request(const std::string& body);

// The answer for a radio map (its floor's transmitters) or a map (the floor whose
// transmitters the scan hears most). Throws ApiError 422 too_few_transmitters (with the
// count heard) when fewer than three known transmitters are heard, 422 no_fix when the
// method finds no position (every transmitter past the cutoff, or in a line).
std::string ranging_answer(store::Store& store, TransmitterCache& cache, bool map_scope, std::int64_t id, const RangingRequest& request);
// The transmitters a scan may hear, as ranging sees them (keyed "type|bssid"): every floor's
// of a map (map_scope) or the radio map's floor's. Read once for a batch of scans.
struct KnownTransmitter {
    std::int64_t floor_id = 0;
    ranging::Transmitter tx;
};
// A transmitter's key in KnownTransmitters: "type|bssid", the bssid normalised.
std::string transmitter_key(std::string_view type, std::string_view bssid);
struct KnownTransmitters {
    bool map_scope = false;
    std::map<std::string, KnownTransmitter> by_key;
};
KnownTransmitters known_transmitters(store::Store& store, TransmitterCache& cache, bool map_scope, std::int64_t id, double phone_height);

// The fix alone, with the same errors: what ranging_answer answers, and what a track fused by a
// Kalman method takes for each scan (POST /v1/tracks/{id}/steps). `known` must have been read
// with the request's phone_height.
Ranged range_scan(const KnownTransmitters& known, const RangingRequest& request);

}  // namespace locus::http
