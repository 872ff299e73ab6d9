#include "sse_listener.hpp"

#include <chrono>

namespace locus::testing {

namespace {

// Polls `done` every 5 ms for up to `seconds`; answers its last value.
template <typename Done>
bool poll(double seconds, Done done) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!done() && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return done();
}

}  // namespace

SseListener::SseListener(int port, const std::string& path, const httplib::Headers& headers, const std::string& source) {
    thread_ = std::thread([this, port, path, headers, source] {
        httplib::Client c("127.0.0.1", port);
        if (!source.empty()) c.set_interface(source);
        c.set_read_timeout(10, 0);
        std::string buf;
        c.Get(path.c_str(), headers, [&](const char* data, std::size_t n) {
            buf.append(data, n);
            for (std::size_t end; (end = buf.find("\n\n")) != std::string::npos; buf.erase(0, end + 2)) {
                const std::string event = buf.substr(0, end);
                const auto d = event.find("\ndata: ");
                if (!event.starts_with("event: ") || d == std::string::npos) continue;  // a heartbeat
                std::lock_guard lock(mu_);
                events_.emplace_back(event.substr(7, d - 7), nlohmann::json::parse(event.substr(d + 7)));
            }
            return !stop_.load();
        });
    });
}

SseListener::~SseListener() {
    stop_ = true;
    thread_.join();
}

std::vector<SseListener::Event> SseListener::seen() {
    std::lock_guard lock(mu_);
    return events_;
}

std::optional<SseListener::Event> SseListener::wait_for(std::size_t n, double seconds) {
    if (!poll(seconds, [&] { return seen().size() >= n; })) return std::nullopt;
    return seen()[n - 1];
}

bool SseListener::ended(double seconds) {
    return poll(seconds, [&] {
        const auto e = seen();
        return !e.empty() && e.back().first == "end";
    });
}

}  // namespace locus::testing
