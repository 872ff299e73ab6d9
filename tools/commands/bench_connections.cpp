// `locus bench connections`: does a running server on loopback hold many clients at once?
// Four kinds of client run together for --seconds:
// - `--active` keep-alive connections sending localize back to back (the phones in use);
// - `--idle` keep-alive connections that each send one /health every --idle-interval
//   seconds, shorter than the server's keep-alive timeout, so they stay open (phones between
//   fixes);
// - `--slowloris` connections that send one byte of an endless request head per second and
//   reconnect when the server cuts them off;
// - a probe that opens a new connection every --probe-interval and times one /health on it
//   (connect included): what a newly arriving phone sees.
// Bounded in connections (≤ 5,000 in all) and time (≤ 300 s); loopback only. Prints one JSON
// object; exits non-zero if any request failed or timed out (10 s).
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <latch>
#include <memory>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench_connection.hpp"
#include "bench_load.hpp"
#include "command_registry.hpp"
#include "survey_connect.hpp"

namespace locus_cli_bench_connections {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct Args {
    ServerArgs server;
    std::int64_t radiomap = 0;
    int active = 100, idle = 900, slowloris = 50;
    double seconds = 30.0, idle_interval = 5.0, probe_interval = 0.1;
    std::string algorithm = "wknn";
};

json latency_summary(std::vector<double>& ms) {
    json out = latency_percentiles(ms);
    out["max_ms"] = ms.empty() ? 0.0 : ms.back();  // sorted by latency_percentiles
    return out;
}

// One raw connection trickling a request head that never ends.
struct SlowClient {
    int fd = -1;
    std::size_t sent = 0;
    ~SlowClient() { drop(); }
    void drop() {
        if (fd >= 0) ::close(fd);
        fd = -1;
    }
    bool connect(const Target& t) {
        drop();
        fd = open_socket(t.host, t.port);
        sent = 0;
        return fd >= 0;
    }
    // Sends the next byte; false when the server has closed or answered (cut us off).
    bool step() {
        static const std::string head = "GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, 0) > 0) return false;  // an answer (408) or the end of the stream
        const char byte = sent < head.size() ? head[sent] : 'a';
        ++sent;
        return ::send(fd, &byte, 1, MSG_NOSIGNAL | MSG_DONTWAIT) == 1;
    }
};

void run(const Args& a) {
    const auto needed = static_cast<rlim_t>(a.active + a.idle + a.slowloris + 64);
    rlimit files{};
    if (::getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < needed) {
        files.rlim_cur = std::min(needed, files.rlim_max);
        ::setrlimit(RLIMIT_NOFILE, &files);
        if (files.rlim_cur < needed)
            throw CommandError("this many connections need " + std::to_string(needed) +
                               " open files; raise the limit (ulimit -n) or ask for fewer");
    }
    const std::string base = a.server.client_options().base_url;
    const Target target = loopback_target(base, "bench connections");
    const auto bodies = localize_bodies(a.server, a.radiomap, "", a.algorithm);
    const std::string path = "/v1/radiomaps/" + std::to_string(a.radiomap) + "/localize";
    std::vector<std::string> requests;
    for (const auto& b : bodies) requests.push_back(http_request("POST", path, target.host_port, b));
    const std::string health = http_request("GET", "/health", target.host_port);

    // Idle and slow clients connect before the clock starts.
    std::vector<std::unique_ptr<BenchConnection>> idle;
    int idle_failed_to_open = 0;
    for (int i = 0; i < a.idle; ++i) {
        idle.push_back(std::make_unique<BenchConnection>(target.host, target.port));
        if (idle.back()->round_trip(health) != 200) ++idle_failed_to_open;
    }
    std::vector<SlowClient> slow(static_cast<std::size_t>(a.slowloris));
    for (auto& s : slow) s.connect(target);

    const auto t0 = Clock::now();
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.seconds));

    // Active clients.
    std::vector<std::vector<double>> active_ms(static_cast<std::size_t>(a.active));
    std::atomic<int> active_errors{0};
    std::latch ready(a.active);
    std::vector<std::thread> threads;
    for (int t = 0; t < a.active; ++t) {
        threads.emplace_back([&, t] {
            BenchConnection c(target.host, target.port);
            c.open();
            ready.count_down();
            auto& lat = active_ms[static_cast<std::size_t>(t)];
            for (std::size_t i = static_cast<std::size_t>(t); Clock::now() < deadline; i += static_cast<std::size_t>(a.active)) {
                const auto s = Clock::now();
                const auto status = c.round_trip(requests[i % requests.size()]);
                if (status == 200) lat.push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
                else ++active_errors;
            }
        });
    }
    ready.wait();

    // Idle clients: each sends one /health per interval, spread over the interval.
    int idle_requests = 0, idle_errors = 0;
    std::thread idle_thread([&] {
        const auto step = std::chrono::duration<double>(a.idle_interval / std::max(1, a.idle));
        auto next = Clock::now();
        for (std::size_t i = 0; !idle.empty() && Clock::now() < deadline; i = (i + 1) % idle.size()) {
            next += std::chrono::duration_cast<Clock::duration>(step);
            std::this_thread::sleep_until(std::min(next, deadline));
            if (Clock::now() >= deadline) break;
            ++idle_requests;
            if (idle[i]->round_trip(health) != 200) ++idle_errors;  // a connection the server dropped, too
        }
    });

    // Slow clients: a byte a second each.
    int cut_off = 0, slow_reconnect_failures = 0;
    std::thread slow_thread([&] {
        while (Clock::now() < deadline) {
            for (auto& s : slow)
                if (!s.step()) {
                    ++cut_off;
                    if (!s.connect(target)) ++slow_reconnect_failures;
                }
            std::this_thread::sleep_until(std::min(Clock::now() + std::chrono::seconds(1), deadline));
        }
    });

    // The probe: a new client's /health, connect included.
    std::vector<double> probe_ms;
    int probe_failures = 0;
    while (Clock::now() < deadline) {
        const auto s = Clock::now();
        BenchConnection fresh(target.host, target.port);
        if (fresh.round_trip(health) == 200) probe_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
        else ++probe_failures;
        std::this_thread::sleep_until(std::min(s + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.probe_interval)), deadline));
    }
    for (auto& th : threads) th.join();
    idle_thread.join();
    slow_thread.join();
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();

    std::vector<double> all_active;
    for (auto& v : active_ms) all_active.insert(all_active.end(), v.begin(), v.end());
    json localize = latency_summary(all_active);
    localize["requests"] = all_active.size() + static_cast<std::size_t>(active_errors.load());
    localize["errors"] = active_errors.load();
    localize["req_per_s"] = static_cast<double>(all_active.size()) / elapsed;
    json probe = latency_summary(probe_ms);
    probe["probes"] = probe_ms.size() + static_cast<std::size_t>(probe_failures);
    probe["failures"] = probe_failures;
    std::cout << json{{"seconds", elapsed},
                      {"connections", a.active + a.idle + a.slowloris},
                      {"localize", localize},
                      {"fresh_health", probe},
                      {"idle", {{"connections", a.idle}, {"failed_to_open", idle_failed_to_open}, {"requests", idle_requests}, {"errors", idle_errors}}},
                      {"slowloris", {{"clients", a.slowloris}, {"cut_off", cut_off}, {"reconnect_failures", slow_reconnect_failures}}},
                      {"algorithm", a.algorithm}}
                     .dump()
              << "\n";
    const int failures = active_errors + idle_errors + idle_failed_to_open + probe_failures;
    if (failures > 0) throw CommandError(std::to_string(failures) + " requests failed or timed out");
}

}  // namespace

LOCUS_COMMAND("bench-connections", [](CLI::App& app) {
    auto& bench = locus::tools::group(app, "bench", "Measure a running server");
    auto* cmd = bench.add_subcommand("connections", "Many clients at once on loopback: active, idle, slow, and a new client's /health latency");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--radiomap", args->radiomap, "radio map the active clients localize against")->required();
    cmd->add_option("--active", args->active, "keep-alive connections sending localize back to back")->capture_default_str()->check(CLI::Range(1, 1000));
    cmd->add_option("--idle", args->idle, "keep-alive connections sending one /health per --idle-interval")->capture_default_str()->check(CLI::Range(0, 4000));
    cmd->add_option("--slowloris", args->slowloris, "connections trickling a request head, a byte a second")->capture_default_str()->check(CLI::Range(0, 1000));
    cmd->add_option("--seconds", args->seconds, "how long the load lasts")->capture_default_str()->check(CLI::Range(1.0, 300.0));
    cmd->add_option("--idle-interval", args->idle_interval, "seconds between an idle client's requests (below the server's keep-alive timeout)")
        ->capture_default_str()->check(CLI::Range(0.1, 60.0));
    cmd->add_option("--probe-interval", args->probe_interval, "seconds between new-client /health probes")->capture_default_str()->check(CLI::Range(0.01, 10.0));
    cmd->add_option("--algorithm", args->algorithm, "the localize algorithm")->capture_default_str();
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_bench_connections
