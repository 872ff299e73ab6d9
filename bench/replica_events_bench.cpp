// Event streams across replicas: how long a fix posted to server A takes to reach an event
// stream open on server B, both servers in this process on 127.0.0.1 sharing one PostgreSQL
// database (the path: A's transaction announces the track, B's change watcher hears the
// NOTIFY, B's refresher reads the track again and wakes the stream). 50 fixes, one at a time,
// each waited for on B (at most 5 s) before the next. Reports the median, p90 and max from
// sending the POST to the event on B, and from A's answer (the fix committed) to the event.
// Argument 0 measures the same with the stream on A itself (the fix posted to its own server),
// for comparison.
// Needs PostgreSQL; run by hand:
//   scripts/with_postgres.sh build/bin/replica_events_bench
// (it uses LOCUS_TEST_DB_URL, which with_postgres.sh sets; LOCUS_REPLICA_EVENTS_FIXES changes 50).
#include <benchmark/benchmark.h>
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <map>
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

double unix_now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

std::int64_t id_of(const httplib::Result& r) {
    if (!r || r->status != 201) throw std::runtime_error("setup request failed");
    return json::parse(r->body).at("id").get<std::int64_t>();
}

double percentile(std::vector<double> v, double p) {
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5)];
}

void BM_FixFromReplicaAToStreamOnB(benchmark::State& state) {
    const char* url = std::getenv("LOCUS_TEST_DB_URL");
    if (!url || !*url) {
        state.SkipWithError("needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)");
        return;
    }
    const char* n_env = std::getenv("LOCUS_REPLICA_EVENTS_FIXES");
    const int n = n_env && *n_env ? std::max(2, std::atoi(n_env)) : 50;
    for (auto _ : state) {
        bench::InProcessServer a(url), b(url);
        httplib::Client ca("127.0.0.1", a.port);
        // A name of its own: map names are unique, and each run adds one to the database.
        const auto map = id_of(ca.Post("/v1/maps", json{{"name", "Replicas " + std::to_string(unix_now())}}.dump(), "application/json"));
        const auto building = id_of(ca.Post("/v1/maps/" + std::to_string(map) + "/buildings", R"({"name": "Mall"})", "application/json"));
        const auto floor = id_of(ca.Post("/v1/buildings/" + std::to_string(building) + "/floors",
                                         R"({"name": "Ground", "level": 0, "width": 200, "height": 100})", "application/json"));
        const auto opened = ca.Post("/v1/tracks", json{{"map_id", map}}.dump(), "application/json");
        const json track = json::parse(opened->body);
        const std::string path = "/v1/tracks/" + std::to_string(track.at("id").get<std::int64_t>());
        const httplib::Headers token{{"X-Track-Token", track.at("token").get<std::string>()}};
        const double t0 = unix_now() - 2.0 * n;
        auto post = [&](int i) {
            const json body = {{"fixes", {{{"t", t0 + i}, {"floor_id", floor}, {"x", 1.0 * i}, {"y", 1.0}, {"accuracy_m", 2.0}}}}};
            const auto r = ca.Post(path + "/fixes", token, body.dump(), "application/json");
            if (!r || r->status != 200) throw std::runtime_error("a fix was refused");
        };
        post(0);

        // B's stream: when each fix (by its index) arrived.
        std::mutex mu;
        std::condition_variable arrived_cv;
        std::map<int, Clock::time_point> arrived;
        std::atomic<bool> stop{false};
        std::thread listener([&] {
            httplib::Client cb("127.0.0.1", state.range(0) ? b.port : a.port);
            cb.set_read_timeout(30, 0);
            std::string buf;
            cb.Get(path + "/events", token, [&](const char* data, std::size_t len) {
                const auto now = Clock::now();
                buf.append(data, len);
                for (std::size_t end; (end = buf.find("\n\n")) != std::string::npos; buf.erase(0, end + 2)) {
                    const std::string event = buf.substr(0, end);
                    const auto d = event.find("\ndata: ");
                    if (!event.starts_with("event: fix") || d == std::string::npos) continue;
                    const int i = static_cast<int>(json::parse(event.substr(d + 7)).at("t").get<double>() - t0 + 0.5);
                    std::lock_guard lock(mu);
                    arrived.emplace(i, now);
                    arrived_cv.notify_all();
                }
                return !stop.load();
            });
        });
        const auto wait_for = [&](int i) {
            std::unique_lock lock(mu);
            return arrived_cv.wait_for(lock, std::chrono::seconds(5), [&] { return arrived.contains(i); });
        };
        std::vector<double> from_send, from_answer;
        if (!wait_for(0)) state.SkipWithError("B's stream never started");
        for (int i = 1; i <= n && !state.error_occurred(); ++i) {
            const auto sent = Clock::now();
            post(i);
            const auto answered = Clock::now();
            if (!wait_for(i)) {
                state.SkipWithError("a fix posted on A never reached B's stream within 5 s");
                break;
            }
            std::lock_guard lock(mu);
            from_send.push_back(std::chrono::duration<double, std::milli>(arrived[i] - sent).count());
            from_answer.push_back(std::chrono::duration<double, std::milli>(arrived[i] - answered).count());
        }
        stop = true;
        post(n + 1);  // wakes the listener's read so it sees `stop`
        listener.join();
        if (from_send.empty()) break;
        state.counters["fixes"] = static_cast<double>(from_send.size());
        state.counters["post_to_B_p50_ms"] = percentile(from_send, 0.5);
        state.counters["post_to_B_p90_ms"] = percentile(from_send, 0.9);
        state.counters["post_to_B_max_ms"] = *std::max_element(from_send.begin(), from_send.end());
        state.counters["answer_to_B_p50_ms"] = percentile(from_answer, 0.5);
        state.counters["answer_to_B_p90_ms"] = percentile(from_answer, 0.9);
    }
}

}  // namespace

BENCHMARK(BM_FixFromReplicaAToStreamOnB)->Arg(1)->Arg(0)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
