#pragma once
// How the track routes answer: the tracks service's refusals (tracks::Refused) as their API
// errors, with Retry-After where waiting helps (docs/tracks.md).
#include <httplib.h>

#include <functional>
#include <nlohmann/json.hpp>
#include <utility>

#include "http/api_error.hpp"
#include "tracks/service.hpp"

namespace locus::http {

// forbidden 403, gone 404 not_found, closed 409 track_closed, busy 503 server_busy, ...
ApiError api_error_of(const tracks::Refused& e);

// Runs a track handler as App::respond does; a Refused becomes its API error.
void respond_track(const httplib::Request& req, httplib::Response& res, const std::function<std::pair<int, nlohmann::json>()>& body);

}  // namespace locus::http
