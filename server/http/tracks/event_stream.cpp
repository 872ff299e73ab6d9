#include "http/tracks/event_stream.hpp"

#include <utility>

#include "http/json_text.hpp"

namespace locus::http {

std::string sse_event(const char* name, const nlohmann::json& data) {
    return std::string("event: ") + name + "\ndata: " + json_text(data) + "\n\n";
}

void begin_event_stream(httplib::Response& res, httplib::ContentProviderWithoutLength provider) {
    res.body.clear();
    // respond() named the body JSON: left, it would be sent beside text/event-stream and
    // gzip would hold the events back until its buffer filled.
    res.headers.erase("Content-Type");
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider("text/event-stream", std::move(provider));
}

}  // namespace locus::http
