#pragma once
// Server-Sent Events for the track and positions streams (docs/tracks.md): an answered-200
// response turned into a chunked text/event-stream fed by a provider.
#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
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

// How often a waiting stream looks whether its reader is still there (seconds).
inline constexpr double kHangUpCheckS = 0.25;

// The next batch of a stream: `next(wait_s)` asked in slices of kHangUpCheckS until it has
// news (`has_news(batch)`) or heartbeat_s have passed (then the empty batch: a heartbeat is
// due). Between slices the reader's connection is checked (ConnectionStream::is_writable sees
// a reader that hung up): nullopt when it is gone, so the stream ends and gives its slot back
// at once, not at its next write, a heartbeat later.
template <typename Next, typename HasNews>
auto next_batch(httplib::DataSink& sink, double heartbeat_s, Next&& next, HasNews&& has_news) -> std::optional<decltype(next(0.0))> {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(heartbeat_s);
    for (;;) {
        const double left = std::chrono::duration<double>(until - std::chrono::steady_clock::now()).count();
        auto batch = next(std::clamp(left, 0.0, kHangUpCheckS));
        if (has_news(batch) || left <= kHangUpCheckS) return batch;
        if (!sink.is_writable()) return std::nullopt;
    }
}

}  // namespace locus::http
