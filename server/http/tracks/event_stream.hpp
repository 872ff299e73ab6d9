#pragma once
// Server-Sent Events for the track and positions streams (docs/tracks.md): an answered-200
// response turned into a chunked text/event-stream fed by a provider.
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>

namespace locus::http {

// "event: <name>\ndata: <json>\n\n"
std::string sse_event(const char* name, const nlohmann::json& data);

// Turns a response that App::respond answered 200 into an event stream fed by `provider`.
void begin_event_stream(httplib::Response& res, httplib::ContentProviderWithoutLength provider);

}  // namespace locus::http
