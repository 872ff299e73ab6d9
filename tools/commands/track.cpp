// `locus track --server URL --map ID [--floor ID] [--speed S] WALK…`: replays walks (walk files
// of ours or PUTMC walk directories) as live tracks, all at once, one track per walk (two
// walks: two people on one floor), so the web map, the event streams and /relative can be
// shown with real movement. The posted points are the walks' ground truth; `locus replay
// --live` posts a fused track instead. Prints one JSON line per track: id, token, walk.
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "command_registry.hpp"
#include "live_track.hpp"
#include "survey_connect.hpp"
#include "walk_points.hpp"

namespace locus_cli_track {
namespace {

using namespace locus;
using namespace locus::tools;

struct Args {
    ServerArgs server;
    std::int64_t map = 0;
    std::int64_t floor = 0;  // 0: the map's first floor
    double speed = 1.0;
    double accuracy_m = 2.0;
    bool keep_open = false;
    std::vector<std::string> walks;
};

api::FloorInfo choose_floor(api::Client& client, const Args& a) {
    if (a.floor != 0) return client.floor(a.floor);
    for (const auto& b : client.buildings(a.map))
        if (auto floors = client.floors(b.id); !floors.empty()) return floors.front();
    throw CommandError("map " + std::to_string(a.map) + " has no floor to track on");
}

void run(const Args& a) {
    api::Client client(a.server.client_options());
    const auto floor = choose_floor(client, a);
    // Read every walk before opening any track: a bad walk then leaves nothing half-posted.
    std::vector<std::vector<LivePoint>> walks;
    for (const auto& w : a.walks) {
        try {
            walks.push_back(walk_points(w, floor.height));
        } catch (const CommandError&) {
            throw;
        } catch (const std::exception& e) {
            throw CommandError(w + ": " + e.what());
        }
    }
    std::mutex out_mutex;
    std::vector<std::string> errors(walks.size());
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < walks.size(); ++i) {
        threads.emplace_back([&, i] {
            try {
                api::Client c(a.server.client_options());
                LiveOptions o;
                o.map_id = a.map;
                o.floor_id = floor.id;
                o.label = std::filesystem::path(a.walks[i]).filename().string();
                o.speed = a.speed;
                o.accuracy_m = a.accuracy_m;
                o.close = !a.keep_open;
                std::ostringstream log;
                const auto key = post_live(c, walks[i], o, log);
                std::lock_guard lock(out_mutex);
                std::cerr << log.str();
                std::cout << nlohmann::json{{"walk", a.walks[i]}, {"id", key.id}, {"token", key.token},
                                            {"fixes", walks[i].size()}}
                                 .dump()
                          << "\n";
            } catch (const std::exception& e) {
                errors[i] = a.walks[i] + ": " + e.what();
            }
        });
    }
    for (auto& t : threads) t.join();
    for (const auto& e : errors)
        if (!e.empty()) throw CommandError("track refused: " + e);
}

}  // namespace

LOCUS_COMMAND("track", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("track", "Replay walks as live tracks (one per walk, all at once)");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--map", args->map, "map of the tracks")->required()->check(CLI::PositiveNumber);
    cmd->add_option("--floor", args->floor, "floor of the map (default: its first)")->check(CLI::PositiveNumber);
    cmd->add_option("--speed", args->speed, "1: real time, 10: ten times faster, 0: all at once")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 10000.0));
    cmd->add_option("--accuracy", args->accuracy_m, "accuracy_m of every fix")->capture_default_str()->check(CLI::Range(0.0, 1000.0));
    cmd->add_flag("--keep-open", args->keep_open, "leave the tracks open after the last fix");
    cmd->add_option("walks", args->walks, "walk files (ours) or PUTMC walk directories")->required()->check(CLI::ExistingPath);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_track
