#pragma once
// POST …/localize with "algorithm": "trilateration" or "multilateration": a position from the
// RSS of transmitters at known positions (the floor's transmitters), not from a radio map's
// RPs; or "proximity": the position of the known transmitter heard strongest ("you are at
// beacon X"), with the range its model gives. Same endpoints and body as the fingerprint
// matchers; their own options (proximity: phone_height only). The ranging itself is
// transmitters/ranging_scan.hpp's.
#include <cstdint>
#include <optional>
#include <string>

#include "http/places_json.hpp"
#include "store/store.hpp"
#include "transmitters/ranging_scan.hpp"
#include "transmitters/transmitter_cache.hpp"

namespace locus::http {

using transmitters::RangingRequest;

// nullopt when the body names no ranging algorithm (the fingerprint parser then reads it).
// Throws ApiError for a bad body that does name one.
std::optional<RangingRequest> parse_ranging_request(const std::string& body);

// The answer for a radio map (its floor's transmitters) or a map (the floor whose
// transmitters the scan hears most). Throws ApiError 422 too_few_transmitters (with the
// count heard) when fewer than three known transmitters are heard, 422 no_fix when the
// method finds no position (every transmitter past the cutoff, or in a line); proximity 422
// no_known_transmitter when the scan hears none.
std::string ranging_answer(store::Store& store, transmitters::TransmitterCache& cache, PositionViews& views, bool map_scope,
                           std::int64_t id, const RangingRequest& request);

}  // namespace locus::http
