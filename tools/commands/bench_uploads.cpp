// `locus bench uploads --server URL [--server URL…]`: scan-upload throughput of one server or
// of several sharing one database, and a proof that concurrent merges are exact. It creates a
// map of its own with --rps RPs on the first server; then --clients threads per server, each
// on a keep-alive connection, post one-scan uploads (two APs, integer RSS from the upload's
// number, a unique upload_id) to the RPs in turn for --seconds. At the end every RP's scan
// count and each AP's count, mean and variance must equal what the acknowledged uploads give
// applied one after another (means to 1e-9: Welford in another order differs in the last
// bits only). Prints one JSON object; exits non-zero on a mismatch or a failed request.
// --radiomap ID adds the --rps RPs to that existing radio map instead (still new, so the check
// stays exact): uploads to a big map, as surveyors extending it, while localize is measured.
#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"

namespace locus_cli_bench_uploads {
namespace {

using namespace locus::tools;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct Args {
    std::vector<std::string> servers{"http://127.0.0.1:8080"};
    int clients = 4;
    int rps = 4;
    double seconds = 10.0;
    std::int64_t radiomap = 0;  // 0: a map of its own
};

// Sums of what the acknowledged uploads sent to one AP of one RP (integers: exact).
struct Sums {
    long long count = 0, sum = 0, sum_sq = 0;
};

std::int64_t created(httplib::Client& c, const std::string& path, const json& body) {
    const auto r = c.Post(path, body.dump(), "application/json");
    if (!r || r->status != 201)
        throw CommandError("creating " + path + " answered " + (r ? std::to_string(r->status) + ": " + r->body : std::string("nothing")));
    return json::parse(r->body).at("id").get<std::int64_t>();
}

const char* const kAps[] = {"bb:00:00:00:00:01", "bb:00:00:00:00:02"};
int rss_of(long long n, int ap) { return ap == 0 ? -40 - static_cast<int>(n % 37) : -55 - static_cast<int>((n * 7) % 29); }

void run(const Args& a) {
    httplib::Client setup(a.servers.front());
    const std::string tag = std::to_string(std::chrono::system_clock::now().time_since_epoch().count());
    json map = nullptr;
    std::int64_t radiomap = a.radiomap;
    if (radiomap == 0) {
        const auto m = created(setup, "/v1/maps", {{"name", "bench uploads " + tag}});
        const auto building = created(setup, "/v1/maps/" + std::to_string(m) + "/buildings", {{"name", "B"}});
        const auto floor = created(setup, "/v1/buildings/" + std::to_string(building) + "/floors",
                                   {{"name", "F"}, {"level", 0}, {"width", 50.0}, {"height", 50.0}});
        radiomap = created(setup, "/v1/floors/" + std::to_string(floor) + "/radiomaps", {{"name", "R"}});
        map = m;
    }
    std::vector<std::int64_t> rps;
    for (int i = 0; i < a.rps; ++i)
        rps.push_back(created(setup, "/v1/radiomaps/" + std::to_string(radiomap) + "/rps",
                              {{"name", "bench uploads " + tag + " rp" + std::to_string(i)}, {"x", 1.0 + i % 40}, {"y", 1.0 + i / 40}}));

    std::mutex mu;
    std::map<std::pair<std::int64_t, int>, Sums> expected;  // (rp, ap) -> sums
    std::map<std::int64_t, long long> scans;
    std::vector<long long> acknowledged(a.servers.size(), 0);
    std::atomic<long long> failed{0};
    std::atomic<long long> next{0};
    const auto start = Clock::now();
    const auto until = start + std::chrono::duration<double>(a.seconds);
    std::vector<std::thread> threads;
    for (std::size_t s = 0; s < a.servers.size(); ++s)
        for (int c = 0; c < a.clients; ++c)
            threads.emplace_back([&, s] {
                httplib::Client http(a.servers[s]);
                http.set_keep_alive(true);
                // The head and the body go out in two writes: without this, each waits for the
                // server's delayed ACK (40 ms) and the figure measures that.
                http.set_tcp_nodelay(true);
                while (Clock::now() < until) {
                    const long long n = next++;
                    const auto rp = rps[static_cast<std::size_t>(n % a.rps)];
                    json scan = json::array();
                    for (int ap = 0; ap < 2; ++ap) scan.push_back({{"type", "wifi"}, {"bssid", kAps[ap]}, {"rss", rss_of(n, ap)}});
                    const json body = {{"upload_id", tag + "-" + std::to_string(n)}, {"scans", json::array({scan})}};
                    const auto r = http.Post("/v1/rps/" + std::to_string(rp) + "/scans", body.dump(), "application/json");
                    if (!r || r->status != 200) {
                        ++failed;
                        continue;
                    }
                    std::lock_guard lock(mu);
                    ++acknowledged[s];
                    ++scans[rp];
                    for (int ap = 0; ap < 2; ++ap) {
                        auto& e = expected[{rp, ap}];
                        ++e.count;
                        e.sum += rss_of(n, ap);
                        e.sum_sq += static_cast<long long>(rss_of(n, ap)) * rss_of(n, ap);
                    }
                }
            });
    for (auto& t : threads) t.join();
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();

    // Read back from the last server: on shared storage every server holds every upload.
    httplib::Client check(a.servers.back());
    json mismatches = json::array();
    for (const auto rp : rps) {
        const auto r = check.Get("/v1/rps/" + std::to_string(rp));
        if (!r || r->status != 200) throw CommandError("reading RP " + std::to_string(rp) + " failed");
        const auto stored = json::parse(r->body);
        if (stored.at("scans").get<long long>() != scans[rp])
            mismatches.push_back({{"rp", rp}, {"scans", stored.at("scans")}, {"acknowledged", scans[rp]}});
        for (const auto& m : stored.at("measurements")) {
            const int ap = m.at("bssid") == kAps[0] ? 0 : 1;
            const auto& e = expected[{rp, ap}];
            const double mean = static_cast<double>(e.sum) / static_cast<double>(e.count);
            const double variance = static_cast<double>(e.sum_sq) / static_cast<double>(e.count) - mean * mean;
            if (m.at("count").get<long long>() != e.count || std::abs(m.at("mean").get<double>() - mean) > 1e-9 ||
                std::abs(m.at("variance").get<double>() - variance) > 1e-6)
                mismatches.push_back({{"rp", rp}, {"bssid", m.at("bssid")}, {"stored", m}, {"count", e.count}, {"mean", mean}, {"variance", variance}});
        }
    }
    long long total = 0;
    for (const auto n : acknowledged) total += n;
    std::cout << json{{"servers", a.servers.size()},
                      {"clients_per_server", a.clients},
                      {"rps", a.rps},
                      {"seconds", seconds},
                      {"uploads", total},
                      {"uploads_by_server", acknowledged},
                      {"uploads_per_s", static_cast<double>(total) / seconds},
                      {"failed", failed.load()},
                      {"exact", mismatches.empty()},
                      {"mismatches", mismatches},
                      {"map_id", map},
                      {"radiomap_id", radiomap}}
                     .dump()
              << "\n";
    if (!mismatches.empty()) throw CommandError("stored statistics differ from the acknowledged uploads");
    if (failed > 0) throw CommandError(std::to_string(failed.load()) + " uploads failed");
}

}  // namespace

LOCUS_COMMAND("bench-uploads", [](CLI::App& app) {
    auto& bench = locus::tools::group(app, "bench", "Measure a running server");
    auto* cmd = bench.add_subcommand("uploads", "Scan-upload throughput of one or several servers, checking the merges are exact");
    auto args = std::make_shared<Args>();
    cmd->add_option("--server", args->servers, "server URL; repeat for servers sharing one database")->capture_default_str();
    cmd->add_option("--clients", args->clients, "keep-alive clients per server")->capture_default_str()->check(CLI::Range(1, 256));
    cmd->add_option("--rps", args->rps, "RPs the uploads share")->capture_default_str()->check(CLI::Range(1, 10000));
    cmd->add_option("--seconds", args->seconds, "how long to upload")->capture_default_str()->check(CLI::Range(0.1, 3600.0));
    cmd->add_option("--radiomap", args->radiomap, "add the RPs to this existing radio map (default: a new map)")->check(CLI::PositiveNumber);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_bench_uploads
