// Live tracks under load (docs/tracks.md): a real server in this process on 127.0.0.1 (the HTTP
// front, the tracks service, SQLite in a temp file), N tracks each posting one fix a second
// for D seconds from 16 kept-alive client connections, and 50 Server-Sent Event listeners on
// 50 of the tracks. Reports the post latency (p50, p99, max), errors, whether every listener
// saw every fix of its track, and the process's resident memory growth. Run by hand:
//   build/bin/track_load_bench                                   # 1,000 tracks, 10 s
//   LOCUS_TRACK_LOAD_SECONDS=60 build/bin/track_load_bench       # the issue's 60 s
// (LOCUS_TRACK_LOAD_TRACKS changes N.) Also BM_PostOneFix: one fix through HTTP, serially.
// Every client sends the server's API key: one address opening a thousand tracks and fifty
// streams is far past the per-client limits (docs/deploy.md), which the key is exempt from.
#include <benchmark/benchmark.h>
#include <httplib.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "in_process_server.hpp"

namespace {

using namespace locus;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

long rss_kib() {
    std::ifstream in("/proc/self/status");
    std::string key;
    long value = 0;
    while (in >> key) {
        if (key == "VmRSS:") {
            in >> value;
            return value;
        }
        in.ignore(1 << 20, '\n');
    }
    return 0;
}

double unix_now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

int env_int(const char* name, int fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::max(1, std::atoi(v)) : fallback;
}

// A temp directory, removed with all it holds at the end.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        char tmpl[] = "/tmp/locus-track-bench.XXXXXX";
        path = mkdtemp(tmpl);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
};

constexpr const char* kApiKey = "track-load-bench";

tracks::Options track_options() {
    tracks::Options o;
    o.max_live_tracks = 100'000;
    return o;
}

// A server in this process, its database in a temp directory (removed after the server), with
// a map of one floor.
struct Server {
    TempDir dir;
    bench::InProcessServer in{(dir.path / "bench.db").string(), track_options(), kApiKey};
    int port = in.port;
    std::int64_t floor = 0, map = 0;

    Server() {
        httplib::Client c("127.0.0.1", port);
        c.set_bearer_token_auth(kApiKey);
        map = json::parse(c.Post("/v1/maps", R"({"name": "Load"})", "application/json")->body)["id"];
        const auto b = json::parse(c.Post("/v1/maps/" + std::to_string(map) + "/buildings", R"({"name": "Mall"})", "application/json")->body)["id"].get<std::int64_t>();
        floor = json::parse(c.Post("/v1/buildings/" + std::to_string(b) + "/floors",
                                   R"({"name": "Ground", "level": 0, "width": 200, "height": 100})", "application/json")->body)["id"];
    }
};

struct OpenTrack {
    std::int64_t id = 0;
    std::string token;
};

OpenTrack open(httplib::Client& c, std::int64_t map) {
    const auto r = c.Post("/v1/tracks", json{{"map_id", map}}.dump(), "application/json");
    const json b = json::parse(r->body);
    return {b["id"].get<std::int64_t>(), b["token"].get<std::string>()};
}

std::string fix_body(double t, std::int64_t floor, double x, double y) {
    return json{{"fixes", {{{"t", t}, {"floor_id", floor}, {"x", x}, {"y", y}, {"accuracy_m", 2.0}, {"heading_deg", 90.0}}}}}.dump();
}

void BM_TrackLoad(benchmark::State& state) {
    const int n_tracks = env_int("LOCUS_TRACK_LOAD_TRACKS", 1000);
    const int seconds = env_int("LOCUS_TRACK_LOAD_SECONDS", 10);
    constexpr int kPosters = 16, kListeners = 50;
    for (auto _ : state) {
        Server server;
        std::vector<OpenTrack> tracks;
        {
            httplib::Client c("127.0.0.1", server.port);
            c.set_bearer_token_auth(kApiKey);
            for (int i = 0; i < n_tracks; ++i) tracks.push_back(open(c, server.map));
        }
        const long rss_before = rss_kib();

        // Listeners, each counting the fix events of its track until the track closes.
        const int listeners = std::min(kListeners, n_tracks);
        std::vector<std::atomic<int>> seen(static_cast<std::size_t>(listeners));
        std::atomic<int> listening{0};
        std::vector<std::thread> listener_threads;
        for (int i = 0; i < listeners; ++i)
            listener_threads.emplace_back([&, i] {
                httplib::Client c("127.0.0.1", server.port);
                c.set_bearer_token_auth(kApiKey);
                c.set_read_timeout(30, 0);
                std::string carry;
                bool counted = false;
                c.Get("/v1/tracks/" + std::to_string(tracks[i].id) + "/events", httplib::Headers{{"X-Track-Token", tracks[i].token}},
                      [&](const char* data, std::size_t n) {
                          if (!counted) {
                              counted = true;
                              ++listening;
                          }
                          carry.append(data, n);
                          for (std::size_t at; (at = carry.find("event: fix")) != std::string::npos; carry.erase(0, at + 10)) ++seen[i];
                          if (carry.size() > 16) carry.erase(0, carry.size() - 16);
                          return true;
                      });
            });
        while (listening < listeners) std::this_thread::sleep_for(std::chrono::milliseconds(10));

        // Posters: track k is posted by thread k % kPosters, once in each one-second slot.
        std::vector<std::vector<double>> latencies(kPosters);
        std::atomic<long> errors{0};
        const auto start = Clock::now();
        const double t0 = unix_now();
        std::vector<std::thread> posters;
        for (int p = 0; p < kPosters; ++p)
            posters.emplace_back([&, p] {
                httplib::Client c("127.0.0.1", server.port);
                c.set_bearer_token_auth(kApiKey);
                c.set_keep_alive(true);
                c.set_tcp_nodelay(true);  // headers and body are two writes: no Nagle wait between them
                for (int s = 0; s < seconds; ++s) {
                    for (int k = p; k < n_tracks; k += kPosters) {
                        const auto began = Clock::now();
                        const auto r = c.Post("/v1/tracks/" + std::to_string(tracks[k].id) + "/fixes",
                                              httplib::Headers{{"X-Track-Token", tracks[k].token}},
                                              fix_body(t0 + s, server.floor, 1.0 + s, 1.0 + k % 90), "application/json");
                        latencies[p].push_back(std::chrono::duration<double, std::milli>(Clock::now() - began).count());
                        if (!r || r->status != 200) ++errors;
                    }
                    std::this_thread::sleep_until(start + std::chrono::seconds(s + 1));
                }
            });
        for (auto& t : posters) t.join();
        const double wall = std::chrono::duration<double>(Clock::now() - start).count();
        const long rss_after = rss_kib();

        // Closing ends each listener's stream; every fix must have been seen by then.
        {
            httplib::Client c("127.0.0.1", server.port);
            c.set_bearer_token_auth(kApiKey);
            for (int i = 0; i < listeners; ++i)
                c.Post("/v1/tracks/" + std::to_string(tracks[i].id) + "/close", httplib::Headers{{"X-Track-Token", tracks[i].token}}, "{}",
                       "application/json");
        }
        for (auto& t : listener_threads) t.join();
        int complete = 0;
        for (int i = 0; i < listeners; ++i) complete += seen[i] == seconds ? 1 : 0;

        std::vector<double> all;
        for (auto& l : latencies) all.insert(all.end(), l.begin(), l.end());
        std::sort(all.begin(), all.end());
        auto pct = [&](double q) { return all.empty() ? 0.0 : all[std::min(all.size() - 1, static_cast<std::size_t>(q * all.size()))]; };
        state.counters["tracks"] = n_tracks;
        state.counters["seconds"] = seconds;
        state.counters["posts"] = static_cast<double>(all.size());
        state.counters["posts_per_s"] = static_cast<double>(all.size()) / wall;
        state.counters["errors"] = static_cast<double>(errors.load());
        state.counters["p50_ms"] = pct(0.50);
        state.counters["p99_ms"] = pct(0.99);
        state.counters["max_ms"] = all.empty() ? 0.0 : all.back();
        state.counters["listeners"] = listeners;
        state.counters["listeners_saw_all"] = complete;
        state.counters["rss_growth_MiB"] = static_cast<double>(rss_after - rss_before) / 1024.0;
    }
}
BENCHMARK(BM_TrackLoad)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

void BM_PostOneFix(benchmark::State& state) {
    Server server;
    httplib::Client c("127.0.0.1", server.port);
    c.set_bearer_token_auth(kApiKey);
    c.set_keep_alive(true);
    c.set_tcp_nodelay(true);
    const OpenTrack t = open(c, server.map);
    const double t0 = unix_now() - 3600;
    long i = 0, errors = 0;
    for (auto _ : state) {
        const auto r = c.Post("/v1/tracks/" + std::to_string(t.id) + "/fixes", httplib::Headers{{"X-Track-Token", t.token}},
                              fix_body(t0 + 0.01 * static_cast<double>(i++), server.floor, 1, 1), "application/json");
        if (!r || r->status != 200) ++errors;
    }
    state.counters["errors"] = static_cast<double>(errors);
}
BENCHMARK(BM_PostOneFix)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
