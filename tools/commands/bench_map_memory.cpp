// `locus bench map-memory --server URL --pid PID`: what one large radio map costs a server
// (docs/deploy.md, capacity). On a running server (a fresh database: the figures are the
// difference this map makes) it builds one map, building and floor of --width × --height m with
// a transmitter every --ap-spacing m, has the server generate a radio map of one RP per
// --step cell from them (POST …/radiomaps/generate: 400 × 250 cells of 1 m = 100,000 RPs, each
// hearing the transmitters modelled above --min-rss), then localizes once on it, which builds
// the radio map's in-memory index. The server's resident memory (VmRSS of /proc/PID/status) is
// read before, after the write and after the index; loopback only, so the PID is on this
// machine. Prints one JSON object; `locus bench localize --radiomap ID` measures throughput on
// the same map afterwards.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <cmath>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench_load.hpp"
#include "command_registry.hpp"
#include "proc_status.hpp"
#include "survey_connect.hpp"

namespace locus_cli_bench_map_memory {
namespace {

using namespace locus::tools;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct Args {
    ServerArgs server;
    int pid = 0;
    double width = 400, height = 250, step = 1.0;
    double ap_spacing = 20, tx_power = -30, path_loss_exponent = 3, min_rss = -80;
    std::int64_t radiomap = 0;  // measure this existing radio map instead of generating one
};

// VmRSS and VmHWM (peak) of a process, in MiB.
struct Memory {
    double rss_mb = 0, peak_mb = 0;
};

Memory memory_of(int pid) {
    const long long rss_kb = proc_status_kb(pid, "VmRSS:"), peak_kb = proc_status_kb(pid, "VmHWM:");
    if (rss_kb < 0 || peak_kb < 0)
        throw CommandError("cannot read /proc/" + std::to_string(pid) + "/status: is --pid the server's process id?");
    return {rss_kb / 1024.0, peak_kb / 1024.0};
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string bssid_of(int i) {
    char buf[18];
    std::snprintf(buf, sizeof buf, "02:00:00:00:%02x:%02x", (i >> 8) & 0xff, i & 0xff);
    return buf;
}

void run(Args a) {
    a.server.server = a.server.client_options().base_url;
    loopback_target(a.server.server, "bench map-memory");
    auto options = a.server.client_options();
    // Generating 100,000 RPs takes a while; a retry of it would make a second radio map.
    options.read_timeout = std::max(options.read_timeout, std::chrono::milliseconds(600'000));
    options.retry.max_attempts = 1;
    locus::api::Client client(options);
    client.get("/health");
    const Memory before = memory_of(a.pid);

    struct Ap {
        double x, y, tx_power, n;
        std::string bssid;
    };
    std::vector<Ap> aps;
    json generated;
    double generate_s = 0;
    std::int64_t radiomap = a.radiomap;
    if (radiomap == 0) {
        const auto map = client.create_map("memory bench " + std::to_string(std::time(nullptr)));
        const auto building = client.create_building(map.id, "B");
        const json floor = client.post("/v1/buildings/" + std::to_string(building.id) + "/floors",
                                       {{"name", "F0"}, {"level", 0}, {"width", a.width}, {"height", a.height}});
        const auto floor_id = floor.at("id").get<std::int64_t>();
        for (double y = a.ap_spacing / 2; y < a.height; y += a.ap_spacing)
            for (double x = a.ap_spacing / 2; x < a.width; x += a.ap_spacing) {
                aps.push_back({x, y, a.tx_power, a.path_loss_exponent, bssid_of(static_cast<int>(aps.size()))});
                client.post("/v1/floors/" + std::to_string(floor_id) + "/transmitters",
                            {{"type", "wifi"}, {"bssid", aps.back().bssid}, {"x", x}, {"y", y}, {"tx_power", a.tx_power},
                             {"path_loss_exponent", a.path_loss_exponent}});
            }
        const auto t0 = Clock::now();
        generated = client.post("/v1/floors/" + std::to_string(floor_id) + "/radiomaps/generate",
                                {{"name", "generated"}, {"step", a.step}, {"min_rss", a.min_rss}, {"sigma_db", 4}});
        generate_s = seconds_since(t0);
        radiomap = generated.at("id").get<std::int64_t>();
    } else {
        // A server started on a database that already holds the map built its index at start:
        // this is what each replica holds. The query comes from the floor's transmitters.
        const json info = client.get("/v1/radiomaps/" + std::to_string(radiomap));
        const auto floor_id = info.at("floor_id").get<std::int64_t>();
        for (std::int64_t offset = 0;; offset += 1000) {
            const json page = client.get("/v1/floors/" + std::to_string(floor_id) + "/transmitters?limit=1000&offset=" +
                                         std::to_string(offset));
            for (const auto& t : page.at("items"))
                aps.push_back({t.at("x").get<double>(), t.at("y").get<double>(), t.at("tx_power").get<double>(),
                               t.value("path_loss_exponent", 2.0), t.at("bssid").get<std::string>()});
            if (page.at("items").size() < 1000) break;
        }
        if (aps.empty()) throw CommandError("radio map " + std::to_string(radiomap) + "'s floor has no transmitters to query with");
        const json floor = client.get("/v1/floors/" + std::to_string(floor_id));
        a.width = floor.at("width").get<double>();
        a.height = floor.at("height").get<double>();
        const json rps = client.get("/v1/radiomaps/" + std::to_string(radiomap) + "/rps?limit=1");
        generated = {{"rp_count", rps.at("total")}, {"measurement_count", nullptr}};
    }
    const Memory written = memory_of(a.pid);

    // A query from the middle of the floor, heard as the model says: the first localize on the
    // radio map builds its index.
    const double qx = a.width / 2, qy = a.height / 2;
    json scan = json::array();
    for (const auto& ap : aps) {
        const double d = std::max(1.0, std::hypot(ap.x - qx, ap.y - qy));
        const double rss = ap.tx_power - 10 * ap.n * std::log10(d);
        if (rss >= a.min_rss) scan.push_back({{"type", "wifi"}, {"bssid", ap.bssid}, {"rss", rss}});
    }
    const json query = {{"scans", json::array({scan})}};
    auto t0 = Clock::now();
    const json first = client.post("/v1/radiomaps/" + std::to_string(radiomap) + "/localize", query);
    const double first_localize_s = seconds_since(t0);
    t0 = Clock::now();
    client.post("/v1/radiomaps/" + std::to_string(radiomap) + "/localize", query);
    const double second_localize_s = seconds_since(t0);
    const Memory indexed = memory_of(a.pid);

    const json out = {
        {"radiomap", radiomap},
        {"rps", generated.at("rp_count")},
        {"measurements", generated.at("measurement_count")},
        {"transmitters", aps.size()},
        {"aps_per_rp", generated.at("measurement_count").is_null()
                           ? json()
                           : json(generated.at("measurement_count").get<double>() / std::max(1.0, generated.at("rp_count").get<double>()))},
        {"generate_s", generate_s},
        {"first_localize_s", first_localize_s},  // index build included
        {"second_localize_s", second_localize_s},
        {"answer", {{"x", first.at("x")}, {"y", first.at("y")}, {"query_x", qx}, {"query_y", qy}}},
        {"rss_mb", {{"before", before.rss_mb}, {"after_write", written.rss_mb}, {"after_index", indexed.rss_mb}}},
        {"peak_rss_mb", indexed.peak_mb},
        {"index_mb", indexed.rss_mb - written.rss_mb},
        {"map_mb", indexed.rss_mb - before.rss_mb},
    };
    std::cout << out.dump(1) << "\n";
}

}  // namespace

LOCUS_COMMAND("bench-map-memory", [](CLI::App& app) {
    auto& bench = locus::tools::group(app, "bench", "Measure a running server");
    auto* cmd = bench.add_subcommand("map-memory",
                                     "Memory a large generated radio map costs a running server (RSS before, after the write, after the index)");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--pid", args->pid, "the server's process id (its /proc/PID/status is read)")->required()->check(CLI::PositiveNumber);
    cmd->add_option("--width", args->width, "floor width (m)")->capture_default_str()->check(CLI::Range(1.0, 10000.0));
    cmd->add_option("--height", args->height, "floor height (m)")->capture_default_str()->check(CLI::Range(1.0, 10000.0));
    cmd->add_option("--step", args->step, "RP grid step (m): one RP per cell")->capture_default_str()->check(CLI::Range(0.1, 1000.0));
    cmd->add_option("--ap-spacing", args->ap_spacing, "a transmitter every this many m, in a grid")->capture_default_str()->check(CLI::Range(1.0, 1000.0));
    cmd->add_option("--min-rss", args->min_rss, "weakest modelled RSS an RP keeps (dBm)")->capture_default_str()->check(CLI::Range(-120.0, 0.0));
    cmd->add_option("--radiomap", args->radiomap,
                    "measure this existing radio map (a server just started on its database) instead of generating one");
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_bench_map_memory
