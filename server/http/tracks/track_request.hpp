#pragma once
// Reading the track routes' requests (docs/tracks.md): the track's token, and the bodies of
// POST /v1/tracks, …/fixes and …/steps, checked in full before anything is written. Bad
// input throws ApiError (422 invalid_field naming the field, 413 batch_too_large, 401 with no
// token); each costs one pass over the body, plus a sort of each list by time.
#include <httplib.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tracks/fusion_method.hpp"
#include "tracks/fusion_options.hpp"
#include "tracks/service.hpp"
#include "tracks/steps_input.hpp"

namespace locus::http {

// At most this many fixes, steps and scans in one request.
inline constexpr std::size_t kMaxFixesPerRequest = 1000;
// At most this many pressure samples in one request (over and above the fixes, steps and
// scans: a barometer reads several times a second).
inline constexpr std::size_t kMaxPressurePerRequest = 5000;
// At most this many GNSS fixes in one request (over and above the rest, as pressure: a
// receiver gives one a second, of which the filter takes one per 10 s).
inline constexpr std::size_t kMaxGnssPerRequest = 1000;
// A GNSS fix's accuracy_m above this (m) places it nowhere near a building.
inline constexpr double kMaxGnssAccuracyM = 10'000;
// A pressure outside this range (hPa) is no barometer's reading at a building's height.
inline constexpr double kMinPressureHpa = 300, kMaxPressureHpa = 1200;
// A phone's clock may run this far ahead of the server's.
inline constexpr double kFutureSlackS = 60;

// The token in `header` (X-Track-Token also as `?token=` on a GET: an EventSource sends no
// headers); 401 when there is none.
std::string token_of(const httplib::Request& req, const char* header = "X-Track-Token");
// 403 forbidden with `refusal` unless the request's token is the owner's of track `id` (the
// Service's Refused for a token that opens nothing).
void require_owner(tracks::Service& svc, const httplib::Request& req, std::int64_t id, const char* refusal);

// POST /v1/tracks {map_id, label?, fusion?, fusion_options?}.
struct OpenRequest {
    std::int64_t map_id = 0;
    std::string label;
    tracks::FusionMethod fusion = tracks::FusionMethod::walk_pf;
    tracks::FusionOptions fusion_options;
};
OpenRequest parse_open_request(const nlohmann::json& body);

// POST /v1/tracks/{id}/fixes {fixes: [{t, floor_id, x, y, accuracy_m, heading_deg?}]}, t no
// older than `retention_s`.
std::vector<tracks::Fix> parse_fixes(const nlohmann::json& body, double retention_s);
// POST /v1/tracks/{id}/steps {steps?, fixes?, scans?, pressure?, gnss?}: at least one item.
tracks::StepsInput parse_steps_request(const nlohmann::json& body, double retention_s);

}  // namespace locus::http
