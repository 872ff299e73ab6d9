// `locus bench thin`: live tracks following the PUTMC walks as thin-client phones (docs/tracks.md,
// "Thin clients") against a running server on loopback. Each track replays a walk's requests
// (tools/putmc_thin: per WiFi scan, one POST /v1/tracks/{id}/steps with the steps confirmed
// since the previous scan and the scan itself, which the server localizes and fuses) at the
// walk's own pace, about one request every 4 s, for --seconds. Track k follows walk k % (the walks) from
// a point of its own, and the tracks' first requests are spread over the first 4 s, so the load
// is even; a walk that ends starts again, its clock carried on. Requests go out on
// --connections keep-alive connections, each sending its tracks' requests when they fall due.
// Sends the API key (one address opening a thousand tracks is far past the per-client limits,
// docs/deploy.md). Prints one JSON object: latency percentiles, errors by status and code, the
// fused fixes the server stored, how late the generator sent (a saturated server or client
// shows there), and with --pid the server's CPU over the load (utime + stime from
// /proc/PID/stat) and its resident memory per track.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <httplib.h>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numbers>
#include <thread>

#include "bench_load.hpp"
#include "command_registry.hpp"
#include "datasets/putmc.hpp"
#include "live_post.hpp"
#include "proc_status.hpp"
#include "putmc_thin.hpp"
#include "survey_connect.hpp"

namespace locus_cli_bench_thin {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct Args {
    ServerArgs server;
    std::string dir;
    std::int64_t map = 0;
    int tracks = 100;
    double seconds = 30.0;
    int connections = 16;
    int server_pid = 0;
};

// One request of a walk, its times on the walk's own clock (s).
struct Request {
    double t = 0.0;
    std::vector<PhoneStep> steps;
    Scan readings;
};
using Walk = std::vector<Request>;

std::vector<Walk> read_walks(const std::string& dir) {
    std::vector<std::string> dirs;
    try {
        dirs = datasets::putmc::walk_dirs(dir);
    } catch (const std::runtime_error& e) {
        throw CommandError(e.what());
    }
    if (dirs.empty()) throw CommandError("'" + dir + "' holds no PUTMC walk (trajs/NAME/acc.map): is it the PUTMC directory?");
    std::vector<Walk> out;
    for (const auto& d : dirs) {
        datasets::putmc::Walk walk;
        try {
            walk = datasets::putmc::read_walk(d);
        } catch (const std::runtime_error& e) {
            throw CommandError(e.what());
        }
        Walk w;
        for (auto& b : walks::thin_batches(walk)) w.push_back({b.t_s, std::move(b.steps), b.scan->readings});
        if (w.size() >= 2) out.push_back(std::move(w));
    }
    if (out.empty()) throw CommandError("'" + dir + "': no PUTMC walk has two scans to replay");
    return out;
}

// The body of request `r`, its times moved by `shift` onto the Unix clock. Without steps when
// `first` (a track's filter starts at a fix: steps before it would be refused).
std::string body_of(const Request& r, double shift, bool first) {
    json steps = json::array();
    if (!first)
        for (const auto& s : r.steps)  // an azimuth in (−π, π]: within the ±360° the server takes
            steps.push_back({{"t", s.t_s + shift}, {"length_m", s.length_m}, {"heading_deg", s.azimuth_rad * 180.0 / std::numbers::pi}});
    return json{{"steps", steps}, {"scans", {{{"t", r.t + shift}, {"readings", readings_json(r.readings)}}}}}.dump();
}

double unix_now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

struct Track {
    std::int64_t id = 0;
    std::string token;
    std::size_t walk = 0, next = 0;
    double shift = 0.0;      // walk clock → Unix clock
    double due_s = 0.0;      // when the next request goes out, s after the start
    bool first = true;
};

void run(const Args& a) {
    const std::string base = a.server.client_options().base_url;
    loopback_target(base, "bench thin");
    const std::vector<Walk> walks = read_walks(a.dir);
    if (a.server_pid && proc_cpu_seconds(a.server_pid) < 0) throw CommandError("--pid " + std::to_string(a.server_pid) + ": no such process");

    httplib::Client http(base);
    http.set_read_timeout(static_cast<time_t>(a.server.timeout_s));
    if (!a.server.api_key.empty()) http.set_bearer_token_auth(a.server.api_key);
    const long long rss_before = a.server_pid ? proc_status_kb(a.server_pid, "VmRSS:") : -1;
    std::vector<Track> tracks(static_cast<std::size_t>(a.tracks));
    const double now = unix_now();
    for (std::size_t k = 0; k < tracks.size(); ++k) {
        const auto r = http.Post("/v1/tracks", json{{"map_id", a.map}, {"label", "bench thin " + std::to_string(k)}}.dump(), "application/json");
        if (!r) throw CommandError("no answer from " + base + ": " + httplib::to_string(r.error()));
        if (r->status != 201) throw CommandError("opening track " + std::to_string(k) + " answered " + std::to_string(r->status) + ": " + r->body.substr(0, 300));
        const json b = json::parse(r->body);
        Track& t = tracks[k];
        t.id = b.at("id").get<std::int64_t>();
        t.token = b.at("token").get<std::string>();
        t.walk = k % walks.size();
        const Walk& w = walks[t.walk];
        t.next = (k / walks.size() * 7) % (w.size() - 1);  // a point of its own along the walk
        t.due_s = 4.0 * static_cast<double>(k) / static_cast<double>(tracks.size());
        t.shift = now + t.due_s - w[t.next].t;
    }

    std::vector<std::vector<double>> latencies(static_cast<std::size_t>(a.connections)), late(latencies.size());
    std::mutex status_mutex;
    std::map<int, long> statuses;  // every non-200 answer by status (0: no answer)
    std::map<std::string, long> codes;
    std::atomic<long> stored{0};  // fused fixes the server stored, over every answer
    const double cpu_before = a.server_pid ? proc_cpu_seconds(a.server_pid) : 0.0;
    const auto start = Clock::now();
    std::vector<std::thread> threads;
    for (int c = 0; c < a.connections; ++c)
        threads.emplace_back([&, c] {
            httplib::Client client(base);
            client.set_keep_alive(true);
            client.set_tcp_nodelay(true);
            client.set_read_timeout(static_cast<time_t>(a.server.timeout_s));
            if (!a.server.api_key.empty()) client.set_bearer_token_auth(a.server.api_key);
            std::vector<Track*> mine;
            for (std::size_t k = static_cast<std::size_t>(c); k < tracks.size(); k += static_cast<std::size_t>(a.connections)) mine.push_back(&tracks[k]);
            if (mine.empty()) return;
            for (;;) {
                Track& t = **std::min_element(mine.begin(), mine.end(), [](const Track* x, const Track* y) { return x->due_s < y->due_s; });
                if (t.due_s >= a.seconds) break;
                std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t.due_s)));
                const Walk& w = walks[t.walk];
                const std::string body = body_of(w[t.next], t.shift, t.first);
                const auto sent = Clock::now();
                late[static_cast<std::size_t>(c)].push_back(std::max(0.0, std::chrono::duration<double>(sent - start).count() - t.due_s) * 1000.0);
                const auto r = client.Post("/v1/tracks/" + std::to_string(t.id) + "/steps", httplib::Headers{{"X-Track-Token", t.token}}, body,
                                           "application/json");
                const double ms = std::chrono::duration<double, std::milli>(Clock::now() - sent).count();
                if (r && r->status == 200) {
                    latencies[static_cast<std::size_t>(c)].push_back(ms);
                    const json answer = json::parse(r->body, nullptr, false);
                    if (answer.is_object()) stored += answer.value("stored", 0L);
                } else {
                    const std::lock_guard lock(status_mutex);
                    ++statuses[r ? r->status : 0];
                    if (r) {
                        const json e = json::parse(r->body, nullptr, false);
                        ++codes[e.is_object() && e.contains("error") ? e["error"].value("code", "?") : "?"];
                    }
                }
                t.first = false;
                if (++t.next == w.size()) {  // the walk again from its start, its clock carried on
                    t.shift += w.back().t - w.front().t + 4.0;
                    t.next = 0;
                }
                const double gap = t.next ? w[t.next].t - w[t.next - 1].t : 4.0;
                t.due_s += gap;
            }
        });
    for (auto& th : threads) th.join();
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    const double cpu_after = a.server_pid ? proc_cpu_seconds(a.server_pid) : 0.0;
    const long long rss_after = a.server_pid ? proc_status_kb(a.server_pid, "VmRSS:") : -1;

    for (const Track& t : tracks) http.Post("/v1/tracks/" + std::to_string(t.id) + "/close", httplib::Headers{{"X-Track-Token", t.token}}, "{}", "application/json");

    std::vector<double> all, lag;
    for (auto& l : latencies) all.insert(all.end(), l.begin(), l.end());
    for (auto& l : late) lag.insert(lag.end(), l.begin(), l.end());
    long errors = 0;
    json by_status = json::object(), by_code = json::object();
    for (const auto& [s, n] : statuses) by_status[std::to_string(s)] = n, errors += n;
    for (const auto& [c, n] : codes) by_code[c] = n;
    const double max_ms = all.empty() ? 0.0 : *std::max_element(all.begin(), all.end());
    json out = latency_percentiles(all);
    out["max_ms"] = max_ms;
    out["requests"] = static_cast<long>(all.size()) + errors;
    out["errors"] = errors;
    out["errors_by_status"] = by_status;
    out["errors_by_code"] = by_code;
    out["fixes_stored"] = stored.load();
    out["requests_per_s"] = static_cast<double>(all.size() + static_cast<std::size_t>(errors)) / wall;
    json lateness = latency_percentiles(lag);
    out["sent_late_ms"] = lateness;  // how far behind schedule requests went out
    out["tracks"] = a.tracks;
    out["walks"] = walks.size();
    out["seconds"] = wall;
    out["connections"] = a.connections;
    if (a.server_pid) {
        out["server_cpu_s"] = cpu_after - cpu_before;
        out["server_cpu_cores"] = (cpu_after - cpu_before) / wall;
        out["server_rss_kb"] = {{"before", rss_before}, {"after", rss_after}};
        if (rss_before >= 0 && rss_after >= 0) out["server_rss_kb_per_track"] = static_cast<double>(rss_after - rss_before) / a.tracks;
    }
    std::cout << out.dump() << "\n";
    if (errors > 0) throw CommandError(std::to_string(errors) + " requests failed; the latency figures leave them out");
}

}  // namespace

LOCUS_COMMAND("bench-thin", [](CLI::App& app) {
    auto& bench = locus::tools::group(app, "bench", "Measure a running server");
    auto* cmd = bench.add_subcommand("thin", "Live tracks replaying the PUTMC walks as thin clients (/steps with scans) on loopback");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("dir", args->dir, "the PUTMC directory (trajs/ under it)")->required()->check(CLI::ExistingDirectory);
    cmd->add_option("--map", args->map, "the map the tracks open on (after `locus import putmc`)")->required();
    cmd->add_option("--tracks", args->tracks, "live tracks, each a phone")->capture_default_str()->check(CLI::Range(1, 10'000));
    cmd->add_option("--seconds", args->seconds, "how long the phones walk")->capture_default_str()->check(CLI::Range(1.0, 600.0));
    cmd->add_option("--connections", args->connections, "keep-alive connections the requests share")->capture_default_str()->check(CLI::Range(1, 256));
    cmd->add_option("--pid", args->server_pid, "the server's process id, to report its CPU and memory from /proc")->check(CLI::PositiveNumber);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_bench_thin
