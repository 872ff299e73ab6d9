#pragma once
// POST …/localize with "algorithm": "trilateration" or "multilateration": a position from the
// RSS of transmitters at known positions (the floor's transmitters), not from a radio map's
// RPs. Same endpoints and body as the fingerprint matchers; its own options. The ranging itself
// is transmitters/ranging_scan.hpp's.
#include <cstdint>
#include <optional>
#include <string>

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
// method finds no position (every transmitter past the cutoff, or in a line).
std::string ranging_answer(store::Store& store, transmitters::TransmitterCache& cache, bool map_scope, std::int64_t id,
                           const RangingRequest& request);

}  // namespace locus::http
