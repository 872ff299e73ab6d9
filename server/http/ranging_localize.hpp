#pragma once
// POST …/localize with "algorithm": "trilateration" or "multilateration": a position from the
// RSS of transmitters at known positions (the floor's transmitters), not from a radio map's
// RPs. Same endpoints and body as the fingerprint matchers; its own options.
#include <optional>
#include <string>

#include "locus/match/query.hpp"
#include "locus/ranging/trilateration.hpp"
#include "http/transmitter_cache.hpp"
#include "store/store.hpp"

namespace locus::http {

struct RangingRequest {
    bool multilateration = false;  // else seed 004's trilateration
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
// The fix alone, with the same errors: what ranging_answer answers, and what a track fused by a
// Kalman method takes for each scan (POST /v1/tracks/{id}/steps).
Ranged range_scan(store::Store& store, TransmitterCache& cache, bool map_scope, std::int64_t id, const RangingRequest& request);

}  // namespace locus::http
