#pragma once
// A server-sent event stream read on a thread of its own (the track and positions streams):
// each event's name and data kept in order, heartbeats skipped, until the listener is destroyed
// or the server ends the stream.
#include <httplib.h>

#include <atomic>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace locus::testing {

class SseListener {
public:
    using Event = std::pair<std::string, nlohmann::json>;

    // `source`: the local address to connect from (127.0.0.2: a second client), else any.
    SseListener(int port, const std::string& path, const httplib::Headers& headers = {}, const std::string& source = "");
    ~SseListener();
    SseListener(const SseListener&) = delete;
    SseListener& operator=(const SseListener&) = delete;

    std::vector<Event> seen();
    // Polls up to `seconds` for the n-th event (from 1); answers it, or nullopt.
    std::optional<Event> wait_for(std::size_t n, double seconds);
    // Polls up to `seconds` for an "end" event as the latest.
    bool ended(double seconds);

private:
    std::mutex mu_;
    std::vector<Event> events_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace locus::testing
