#pragma once
// Server-Sent Events for the track and positions streams (docs/tracks.md): an answered-200
// response turned into a chunked text/event-stream fed by a provider.
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>

namespace locus::http {

// "event: <name>\ndata: <json>\n\n"
std::string sse_event(const char* name, const nlohmann::json& data);

// The `end` event's reason for a stream the server ended to let another client's stream in
// (tracks/event_streams.hpp).
inline constexpr const char* kEvicted =
    "evicted: the server's event streams were full and this client held the most; another client's stream took its place";

// Turns a response that App::respond answered 200 into an event stream fed by `provider`.
void begin_event_stream(httplib::Response& res, httplib::ContentProviderWithoutLength provider);

}  // namespace locus::http
