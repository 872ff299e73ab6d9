// `locus import ipin DIR --server URL [--map NAME] [--trials GLOB] [--cell M]`: the IPIN 2023
// Track 3 folder (trials/ and supplementary/, docs/ipin-import.md) into a map through the public API:
// building "100", floors 0, -1, -2 (level = the POSI floor id) in one frame georeferenced from
// the data set's local frame (tools/ipin_venue.hpp), the six competition beacons as
// transmitters, and per floor the radio map "IPIN 2023 walking survey" made from the selected
// trials' WiFi scans by the walking survey (locus/survey/walk.hpp).
//
// Every file is read and checked before the first request, so bad input (a missing folder or
// file, a malformed CSV line, a logfile error) changes nothing on the server. Re-runnable: the
// hierarchy is found by name, floors and transmitters are patched only where they differ, and
// every RP upload carries "walk-<content hash of the logfile>-<cell>", so a second run
// changes nothing.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/ipin_log.hpp"
#include "datasets/walk_files.hpp"
#include "ipin_venue.hpp"
#include "survey_connect.hpp"
#include "survey_upload.hpp"
#include "walk_survey.hpp"

namespace locus_cli_import_ipin {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;
namespace fs = std::filesystem;

constexpr const char* kRadioMapName = "IPIN 2023 walking survey";
// An iBeacon's advertised power at 1 m is typically about -59 dBm; the logs' "power" column
// is not meaningful (the data set's README), so this is a starting value for a model fit.
constexpr double kBeaconTxPower = -59.0;

struct Args {
    ServerArgs server;
    std::string dir;
    std::string map = "IPIN 2023 Nuremberg";
    std::vector<std::string> trials{"*.txt"};
    double cell = 5.0;
    int concurrency = 4;
    bool progress = true;
};

bool near(const json& j, const char* key, double v) {
    const auto it = j.find(key);
    return it != j.end() && it->is_number() && std::abs(it->get<double>() - v) < 1e-9;
}

void run(const Args& a) {
    // 1. Everything from the files first: nothing is sent unless all of it reads.
    const fs::path dir(a.dir);
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw CommandError("'" + a.dir + "' is not a folder");
    const std::string ble_path = (dir / "supplementary" / "BLE_Locations.csv").string();
    if (!fs::is_regular_file(ble_path, ec)) throw CommandError("'" + ble_path + "' is missing: is '" + a.dir + "' the IPIN 2023 folder?");
    std::vector<datasets::IpinBeacon> beacons;
    std::vector<std::string> files;
    try {
        beacons = datasets::parse_ipin_beacons(read_file(ble_path), ble_path);
        files = ipin::trial_files(a.dir, a.trials);
    } catch (const std::runtime_error& e) {
        throw CommandError(std::string(e.what()) + "; nothing imported");
    }
    const auto& venue = ipin::venue_floors();
    for (const auto& b : beacons)
        if (std::none_of(venue.begin(), venue.end(), [&](const ipin::FloorSpec& f) { return f.level == b.floor; }))
            throw CommandError(ble_path + ":" + std::to_string(b.line) + ": floor " + std::to_string(b.floor) +
                               " is not one of the venue's (0, -1, -2); nothing imported");
    if (files.empty()) throw CommandError("no file of '" + (dir / "trials").string() + "' matches --trials");

    const geo::FloorToEarth frame(ipin::venue_georeference());
    const ToFloor to_floor = [&](int floor, double lat, double lon) -> std::optional<Point> {
        const auto& floors = ipin::venue_floors();
        if (std::none_of(floors.begin(), floors.end(), [&](const ipin::FloorSpec& f) { return f.level == floor; }))
            return std::nullopt;
        return frame.to_floor(geo::LatLon{lat, lon});
    };
    std::vector<Walk> walks;
    std::size_t unknown_floor_landmarks = 0;
    for (const auto& path : files) {
        std::cerr << "reading " << path << "\n";
        const std::string bytes = read_file(path);
        datasets::ipin::Log log;
        try {
            log = datasets::ipin::parse_log(bytes, path);
        } catch (const datasets::ipin::LogError& e) {
            throw CommandError(std::string(e.what()) + "; nothing imported");
        }
        Walk w;
        w.source = path;
        w.stem = ipin::trial_label(path);
        w.content = fingerprint(bytes);
        std::size_t dropped = 0;
        w.landmarks = landmarks_of_posi(log, to_floor, dropped);
        unknown_floor_landmarks += dropped;
        add_wifi_scans(log, w);
        walks.push_back(std::move(w));
    }
    // Floors cover the frame; a landmark or beacon outside it would grow them.
    double width = ipin::kWidth, height = ipin::kHeight;
    auto cover = [&](Point p) {
        width = std::max(width, std::ceil(p.x + 5.0));
        height = std::max(height, std::ceil(p.y + 5.0));
        if (p.x < 0 || p.y < 0)
            throw CommandError("a position lies west or south of the venue frame (" + std::to_string(p.x) + ", " +
                               std::to_string(p.y) + "): is this the IPIN 2023 Nuremberg venue? nothing imported");
    };
    for (const auto& w : walks)
        for (const auto& l : w.landmarks) cover(l.at);
    for (const auto& b : beacons) cover(frame.to_floor({b.lat, b.lon}));

    // 2. The hierarchy.
    const auto options = a.server.client_options();
    api::Client client(options);
    const auto map = client.ensure_map(a.map, "IPIN 2023 Track 3 training walks (Museum Industriekultur, Nuremberg)");
    const auto building = client.ensure_building(map.id, "100", "IPIN 2023 building id 100");
    const auto g = ipin::venue_georeference();
    const json geo = {{"lat", g.at.lat}, {"lon", g.at.lon}, {"x", g.anchor.x}, {"y", g.anchor.y}, {"bearing_deg", g.bearing_deg}};
    std::map<int, std::int64_t> floor_ids;
    std::size_t floors_patched = 0;
    json floors_out = json::array();
    for (const auto& spec : ipin::venue_floors()) {
        api::FloorInfo f;
        f.building_id = building.id;
        f.name = spec.name;
        f.level = spec.level;
        f.width = width;
        f.height = height;
        const auto floor = client.ensure_floor(f);
        floor_ids[spec.level] = floor.id;
        const json stored = client.get("/v1/floors/" + std::to_string(floor.id));
        json patch = json::object();
        if (!near(stored, "width", width) || !near(stored, "height", height)) {
            patch["width"] = std::max(width, stored.value("width", 0.0));
            patch["height"] = std::max(height, stored.value("height", 0.0));
        }
        if (stored.value("level", 1 << 20) != spec.level) patch["level"] = spec.level;
        if (!near(stored, "elevation_m", spec.elevation_m)) patch["elevation_m"] = spec.elevation_m;
        const json sg = stored.contains("geo") ? stored.at("geo") : json();
        if (!sg.is_object() || !near(sg, "lat", g.at.lat) || !near(sg, "lon", g.at.lon) || !near(sg, "x", g.anchor.x) ||
            !near(sg, "y", g.anchor.y) || !near(sg, "bearing_deg", g.bearing_deg))
            patch["geo"] = geo;
        if (!patch.empty()) {
            client.patch("/v1/floors/" + std::to_string(floor.id), patch);
            ++floors_patched;
        }
        floors_out.push_back({{"level", spec.level}, {"floor_id", floor.id}, {"name", spec.name}, {"elevation_m", spec.elevation_m}});
    }
    std::cerr << "map " << map.id << " '" << a.map << "', building " << building.id << ", floors";
    for (const auto& [level, id] : floor_ids) std::cerr << " " << level << "=" << id;
    std::cerr << "\n";

    // 3. The beacons, created or patched where they differ.
    std::size_t tx_created = 0, tx_updated = 0, tx_unchanged = 0;
    std::map<std::int64_t, std::map<std::string, json>> existing;  // floor -> bssid -> row
    for (const auto& [level, id] : floor_ids)
        for (const auto& t : client.list_all("/v1/floors/" + std::to_string(id) + "/transmitters"))
            if (t.value("type", "") == "ble") existing[id][t.value("bssid", "")] = t;
    for (const auto& b : beacons) {
        const std::int64_t fid = floor_ids.at(b.floor);
        const Point at = frame.to_floor({b.lat, b.lon});
        const std::string mac = ipin::beacon_mac(ipin::logged_beacon(b.number));
        const json body = {{"name", b.name}, {"type", "ble"}, {"bssid", mac},
                           {"x", at.x},      {"y", at.y},     {"tx_power", kBeaconTxPower}};
        // By its MAC, else by its name: a map imported when BLE2 and BLE3 had the MACs of their
        // numbers (ipin::logged_beacon) has its rows moved to the right MAC, not doubled.
        auto it = existing[fid].find(mac);
        if (it == existing[fid].end())
            it = std::find_if(existing[fid].begin(), existing[fid].end(),
                              [&](const auto& row) { return row.second.value("name", "") == b.name; });
        try {
            if (it == existing[fid].end()) {
                client.post("/v1/floors/" + std::to_string(fid) + "/transmitters", body);
                ++tx_created;
            } else if (it->first != mac || it->second.value("name", "") != b.name || !near(it->second, "x", at.x) ||
                       !near(it->second, "y", at.y)) {
                client.patch("/v1/transmitters/" + std::to_string(it->second.at("id").get<std::int64_t>()),
                             {{"name", b.name}, {"bssid", mac}, {"x", at.x}, {"y", at.y}});
                ++tx_updated;
            } else {
                ++tx_unchanged;
            }
        } catch (const api::ApiError& e) {
            throw CommandError(ble_path + ":" + std::to_string(b.line) + ": " + plain_numbers(e.what()));
        }
    }

    // 4. The radio maps: one per floor the selected walks' placed scans reach.
    WalkCounts counts;
    std::map<int, std::int64_t> radiomap_of_floor;
    std::vector<std::vector<RpJob>> per_walk;
    {
        // Which floors get scans does not depend on the radio maps' ids: place with stand-ins.
        std::map<int, std::int64_t> all;
        for (const auto& [level, id] : floor_ids) all[level] = level;
        WalkCounts probe;
        for (const auto& w : walks) {
            try {
                per_walk.push_back(walk_jobs(w, all, a.cell, probe));
            } catch (const std::invalid_argument& e) {
                throw CommandError(w.source + ": " + e.what());
            }
        }
        counts = probe;
        for (const auto& [level, n] : probe.rps_per_floor)
            if (n > 0) radiomap_of_floor[level] = client.ensure_radiomap(floor_ids.at(level), kRadioMapName,
                                                                         "walking survey, cell " + cell_text(a.cell) + " m").id;
    }
    std::vector<RpJob> jobs;
    for (auto& walk : per_walk)
        for (auto& j : walk) {
            j.radiomap_id = radiomap_of_floor.at(static_cast<int>(j.radiomap_id));
            jobs.push_back(std::move(j));
        }
    UploadOptions uo;
    uo.concurrency = a.concurrency;
    uo.progress = a.progress && isatty(2);
    const auto summary = upload_rps(options, jobs, uo);
    for (auto& f : floors_out) {
        const int level = f.at("level").get<int>();
        if (radiomap_of_floor.count(level)) {
            f["radiomap_id"] = radiomap_of_floor.at(level);
            f["rps"] = counts.rps_per_floor[level];
            f["scans"] = counts.scans_per_floor[level];
        } else {
            f["radiomap_id"] = nullptr;
        }
    }
    json out = {{"map_id", map.id},
                {"building_id", building.id},
                {"floors", floors_out},
                {"floors_patched", floors_patched},
                {"transmitters", {{"created", tx_created}, {"updated", tx_updated}, {"unchanged", tx_unchanged}}},
                {"trials", files.size()},
                {"cell_m", a.cell},
                {"walk", counts.to_json()},
                {"landmarks_on_unknown_floors", unknown_floor_landmarks},
                {"upload", summary.to_json()}};
    std::cout << out.dump() << "\n";
    for (const auto& f : summary.failures) std::cerr << "locus: " << f << "\n";
    if (summary.failed > 0) throw CommandError(std::to_string(summary.failed) + " RPs failed to upload; re-run to retry them");
}

}  // namespace

LOCUS_COMMAND("import-ipin", [](CLI::App& app) {
    auto& import = locus::tools::group(app, "import", "Import radio maps from other systems' data through the server API");
    auto* cmd = import.add_subcommand("ipin", "Import the IPIN 2023 Track 3 folder: venue, beacons, walking-survey radio maps (docs/ipin-import.md)");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("DIR", args->dir, "the data set folder (with trials/ and supplementary/)")->required();
    cmd->add_option("--map", args->map, "map name (found or created)")->capture_default_str();
    cmd->add_option("--trials", args->trials, "which files of DIR/trials to survey from: globs on the file name (repeat: any matches)")
        ->capture_default_str();
    cmd->add_option("--cell", args->cell, "pool a walk's scans into RPs of this many metres along the path (0: one RP per scan)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1000.0));
    cmd->add_option("--concurrency", args->concurrency, "parallel connections")->capture_default_str()->check(CLI::Range(1, 64));
    locus::tools::add_no_progress_flag(*cmd, args->progress);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_import_ipin
