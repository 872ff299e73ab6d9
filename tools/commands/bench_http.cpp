// `locus bench localize`: HTTP throughput and latency of a running server on loopback, for
// POST /v1/radiomaps/{id}/localize replaying real scans and, as the yardstick, GET /health.
// C threads each keep one connection alive and send requests back to back; bounded by
// --requests and --max-seconds. Requests are built before the clock starts and each goes out
// in one write (tools/bench_connection.hpp says why). The two kinds alternate in --rounds
// rounds (localize, health, localize, ...), so a change in the machine's background load
// during the run weighs on both alike instead of on whichever phase it hit. Prints one JSON
// object.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <iostream>
#include <latch>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "bench_connection.hpp"
#include "bench_load.hpp"
#include "command_registry.hpp"
#include "survey_connect.hpp"

namespace locus_cli_bench_http {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct Args {
    ServerArgs server;
    std::int64_t radiomap = 0;
    int concurrency = 4;
    int requests = 20000;
    double max_seconds = 60.0;
    std::string scans_file;
    std::string algorithm = "wknn";
    int warmup = 200;
    int rounds = 5;
};

// What one kind of request did, over one or several rounds.
struct Phase {
    std::vector<double> latencies_ms;  // answered 200
    int errors = 0;
    double seconds = 0.0;

    void add(Phase&& other) {
        latencies_ms.insert(latencies_ms.end(), other.latencies_ms.begin(), other.latencies_ms.end());
        errors += other.errors;
        seconds += other.seconds;
    }
    double per_second() const { return seconds > 0 ? static_cast<double>(latencies_ms.size()) / seconds : 0.0; }
};

// `count` requests, request i being requests[(first + i) % size], on C connections.
Phase run_phase(const Args& a, int count, double max_seconds, const Target& target, const std::vector<std::string>& requests,
                std::size_t first) {
    std::atomic<int> next{0};
    std::atomic<int> errors{0};
    std::vector<std::vector<double>> latencies(static_cast<std::size_t>(a.concurrency));
    // Threads start and connect before the clock does, so neither is timed.
    std::latch ready(a.concurrency);
    std::latch go(1);
    Clock::time_point deadline;
    std::vector<std::thread> threads;
    for (int t = 0; t < a.concurrency; ++t) {
        threads.emplace_back([&, t] {
            BenchConnection connection(target.host, target.port);
            connection.open();  // a failure shows as errors on the first request
            auto& lat = latencies[static_cast<std::size_t>(t)];
            lat.reserve(static_cast<std::size_t>(count / a.concurrency + 1));
            ready.count_down();
            go.wait();
            for (;;) {
                const int i = next++;
                if (i >= count || Clock::now() > deadline) break;
                const auto s = Clock::now();
                const auto status = connection.round_trip(requests[(first + static_cast<std::size_t>(i)) % requests.size()]);
                // A failure (often an instant refusal) is counted, not timed: it would make a
                // failing server look fast.
                if (status == 200) lat.push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
                else ++errors;
            }
        });
    }
    ready.wait();
    const auto t0 = Clock::now();
    deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(max_seconds));
    go.count_down();
    for (auto& th : threads) th.join();
    Phase out;
    out.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    out.errors = errors.load();
    for (auto& l : latencies) out.latencies_ms.insert(out.latencies_ms.end(), l.begin(), l.end());
    return out;
}

json summary(Phase& p) {
    json out = latency_percentiles(p.latencies_ms);
    out["requests"] = p.latencies_ms.size() + static_cast<std::size_t>(p.errors);
    out["errors"] = p.errors;
    out["seconds"] = p.seconds;
    out["req_per_s"] = p.per_second();  // answered 200
    return out;
}

void run(Args a) {
    a.server.server = a.server.client_options().base_url;
    const Target target = loopback_target(a.server.server, "bench localize");
    httplib::Client http(a.server.server);
    const auto bodies = localize_bodies(a.server, a.radiomap, a.scans_file, a.algorithm);
    const std::string path = "/v1/radiomaps/" + std::to_string(a.radiomap) + "/localize";
    {
        auto r = http.Post(path, bodies.front(), "application/json");
        if (!r) throw CommandError("no answer from " + a.server.server);
        if (r->status != 200) throw CommandError("localize answered " + std::to_string(r->status) + ": " + r->body.substr(0, 300));
    }
    std::vector<std::string> localize_requests;
    localize_requests.reserve(bodies.size());
    for (const auto& b : bodies) localize_requests.push_back(http_request("POST", path, target.host_port, b));
    const std::vector<std::string> health_requests{http_request("GET", "/health", target.host_port)};
    run_phase(a, std::min(a.warmup, a.requests), a.max_seconds, target, localize_requests, 0);
    Phase localize, health;
    json ratio_by_round = json::array();
    const int rounds = std::min(a.rounds, a.requests);
    for (int r = 0; r < rounds; ++r) {
        const int count = a.requests / rounds + (r < a.requests % rounds ? 1 : 0);
        Phase l = run_phase(a, count, a.max_seconds / rounds, target, localize_requests,
                            static_cast<std::size_t>(r) * static_cast<std::size_t>(a.requests / rounds));
        Phase h = run_phase(a, count, a.max_seconds / rounds, target, health_requests, 0);
        ratio_by_round.push_back(h.per_second() > 0 ? l.per_second() / h.per_second() : 0.0);
        localize.add(std::move(l));
        health.add(std::move(h));
    }
    const double ratio = health.per_second() > 0 ? localize.per_second() / health.per_second() : 0.0;
    std::cout << json{{"localize", summary(localize)},
                      {"health", summary(health)},
                      {"localize_over_health", ratio},
                      {"ratio_by_round", ratio_by_round},
                      {"concurrency", a.concurrency},
                      {"distinct_scans", bodies.size()},
                      {"algorithm", a.algorithm}}
                     .dump()
              << "\n";
    const int errors = localize.errors + health.errors;
    if (errors > 0) throw CommandError(std::to_string(errors) + " requests failed; the figures above leave them out");
}

}  // namespace

LOCUS_COMMAND("bench-localize", [](CLI::App& app) {
    auto& bench = locus::tools::group(app, "bench", "Measure a running server");
    auto* cmd = bench.add_subcommand("localize", "Localize and /health throughput and latency on loopback keep-alive connections");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--radiomap", args->radiomap, "radio map to localize against")->required();
    cmd->add_option("--concurrency", args->concurrency, "parallel keep-alive connections")->capture_default_str()->check(CLI::Range(1, 256));
    cmd->add_option("--requests", args->requests, "requests per kind (localize, health), spread over the rounds")->capture_default_str()->check(CLI::Range(1, 1'000'000));
    cmd->add_option("--rounds", args->rounds, "localize and health phases alternate this many times")->capture_default_str()->check(CLI::Range(1, 100));
    cmd->add_option("--max-seconds", args->max_seconds, "time limit per kind of request")->capture_default_str()->check(CLI::Range(0.1, 600.0));
    cmd->add_option("--scans", args->scans_file, "scans to replay: UJIIndoorLoc CSV or a survey file (default: the RPs' own means)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--algorithm", args->algorithm, "bsb, nn, bsbnn, knn, wknn, bayes")->capture_default_str();
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_bench_http
