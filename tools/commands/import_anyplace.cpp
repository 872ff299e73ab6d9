// `locus import anyplace --server URL --map NAME DIR`: Anyplace rss-log files (every file
// named rss-log under DIR, or DIR itself when it is a file) into one building named after DIR.
// Latitude/longitude are projected to metres east/north of the south-west corner of all the
// points (shared by every floor, so floors stack); each distinct (floor, lat, lon) is an RP
// and the lines sharing a timestamp there are one scan. Floor "Floor <f>", level f, one radio
// map "anyplace" per floor, size = the extent + 1 m. Upload ids: content hash of each file.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/survey_sources.hpp"
#include "survey_connect.hpp"
#include "survey_upload.hpp"

namespace locus_cli_import_anyplace {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;
namespace fs = std::filesystem;

struct Args {
    ServerArgs server;
    std::string map = "Anyplace";
    std::string building;
    std::string dir;
    bool progress = true;
};

struct Loaded {
    std::string path, upload_id;
    datasets::survey::AnyplaceData data;
};

void run(const Args& a) {
    std::vector<std::string> paths;
    if (fs::is_directory(a.dir)) {
        for (const auto& e : fs::recursive_directory_iterator(a.dir))
            if (e.is_regular_file() && e.path().filename() == "rss-log") paths.push_back(e.path().string());
    } else {
        paths.push_back(a.dir);
    }
    std::sort(paths.begin(), paths.end());
    if (paths.empty()) throw CommandError("no rss-log file under " + a.dir);

    std::vector<Loaded> files;
    double lat0 = INFINITY, lon0 = INFINITY;
    std::size_t malformed = 0;
    for (const auto& p : paths) {
        const std::string bytes = read_file(p);
        Loaded l{p, "anyplace-" + fingerprint(bytes), datasets::survey::parse_anyplace(bytes)};
        for (const auto& e : l.data.errors) std::cerr << p << ":" << e.line << ": " << e.message << "\n";
        malformed += l.data.errors.size();
        for (const auto& line : l.data.lines) lat0 = std::min(lat0, line.lat), lon0 = std::min(lon0, line.lon);
        files.push_back(std::move(l));
    }
    if (!std::isfinite(lat0)) throw CommandError("no usable line in " + a.dir);
    double width = 0.0, height = 0.0;
    for (const auto& f : files)
        for (const auto& line : f.data.lines) {
            const Point p = datasets::survey::project(line.lat, line.lon, lat0, lon0);
            width = std::max(width, p.x), height = std::max(height, p.y);
        }

    const auto options = a.server.client_options();
    api::Client client(options);
    const auto map = client.ensure_map(a.map, "Imported from Anyplace rss-log files");
    std::string building_name = a.building;
    if (building_name.empty()) building_name = fs::path(a.dir).lexically_normal().filename().string();
    if (building_name.empty()) building_name = fs::path(a.dir).lexically_normal().parent_path().filename().string();
    char origin[96];
    std::snprintf(origin, sizeof origin, "origin lat=%.8f lon=%.8f (x east, y north, metres)", lat0, lon0);
    const auto building = client.ensure_building(map.id, building_name, origin);

    std::map<std::string, std::int64_t> radiomap_of;
    json radiomap_list = json::array();
    std::vector<RpJob> jobs;
    for (const auto& f : files) {
        // (floor, RP name) -> job; timestamp -> scan index within the job.
        std::map<std::pair<std::string, std::string>, std::pair<std::size_t, std::map<long long, std::size_t>>> index;
        for (const auto& line : f.data.lines) {
            if (!radiomap_of.count(line.floor)) {
                api::FloorInfo fl;
                fl.building_id = building.id;
                fl.name = "Floor " + line.floor;
                try {
                    fl.level = std::stoi(line.floor);
                } catch (const std::exception&) {
                    fl.level = 0;
                }
                fl.width = width + 1.0;
                fl.height = height + 1.0;
                const auto floor = client.ensure_floor(fl);
                radiomap_of[line.floor] = client.ensure_radiomap(floor.id, "anyplace", "RPs from Anyplace rss-log").id;
                radiomap_list.push_back({{"id", radiomap_of[line.floor]}, {"name", "anyplace"}, {"building", building.name},
                                         {"building_id", building.id}, {"floor", fl.name}, {"floor_id", floor.id}});
            }
            char name[64];
            std::snprintf(name, sizeof name, "ap_%.7f_%.7f", line.lat, line.lon);
            auto [it, fresh] = index.try_emplace({line.floor, name});
            if (fresh) {
                it->second.first = jobs.size();
                RpJob job;
                job.radiomap_id = radiomap_of.at(line.floor);
                job.name = name;
                job.at = datasets::survey::project(line.lat, line.lon, lat0, lon0);
                job.upload_id = f.upload_id;
                job.source = f.path;
                jobs.push_back(std::move(job));
            }
            auto& job = jobs[it->second.first];
            auto [scan, new_scan] = it->second.second.try_emplace(line.timestamp, job.scans.size());
            if (new_scan) job.scans.emplace_back();
            auto& s = job.scans[scan->second];
            // A repeated AP within one scan is a logging duplicate: keep the first reading.
            if (std::none_of(s.begin(), s.end(), [&](const Reading& r) { return r.bssid == line.bssid; }))
                s.push_back({"wifi", line.bssid, line.rss});
        }
    }
    UploadOptions uo;
    uo.progress = a.progress && isatty(2);
    const auto summary = upload_rps(options, jobs, uo);
    json out = summary.to_json();
    out["map_id"] = map.id;
    out["building_id"] = building.id;
    out["floors"] = radiomap_of.size();
    out["radiomap_list"] = radiomap_list;
    out["files"] = paths;
    out["malformed_lines"] = malformed;
    out["origin"] = {{"lat", lat0}, {"lon", lon0}};
    std::cout << out.dump() << "\n";
    print_radiomaps(radiomap_list);
    for (const auto& fl : summary.failures) std::cerr << "locus: " << fl << "\n";
    if (summary.failed > 0) throw CommandError(std::to_string(summary.failed) + " RPs failed to upload; re-run to retry them");
}

}  // namespace

LOCUS_COMMAND("import-anyplace", [](CLI::App& app) {
    auto& import = locus::tools::group(app, "import", "Import radio maps from other systems' data through the server API");
    auto* cmd = import.add_subcommand("anyplace", "Import Anyplace rss-log files (degrees projected to local metres)");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--map", args->map, "map name (created if missing)")->capture_default_str();
    cmd->add_option("--building", args->building, "building name (default: the folder's name)");
    locus::tools::add_no_progress_flag(*cmd, args->progress);
    cmd->add_option("DIR", args->dir, "folder holding rss-log files (searched recursively), or one rss-log file")
        ->required()
        ->check(CLI::ExistingPath);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_import_anyplace
