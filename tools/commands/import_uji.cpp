// `locus import uji --server URL --map NAME FILE`: the UJIIndoorLoc training CSV into a map
// through the public API. Buildings "Building <B>", floors "Floor <F>" (level F), one radio
// map "UJIIndoorLoc building <B> floor <F>" per floor, one RP per distinct (building, floor, longitude, latitude).
//
// Coordinates: the CSV's projected metres minus a per-building origin (the smallest
// LONGITUDE and LATITUDE seen in that building), so every floor of a building shares one
// frame starting at (0, 0) as docs/spec.md §2.1 wants; the origin is written into the building's
// description ("utm_origin=X0,Y0") and printed, and CSV coordinates are recovered as
// (x + X0, y + Y0). Floor width/height = the building's extent + 1 m.
//
// Re-runnable: every RP upload carries upload_id "uji-<content hash of FILE>", so importing
// the same file again merges nothing twice.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/uji_csv.hpp"
#include "survey_connect.hpp"
#include "survey_upload.hpp"

namespace locus_cli_import_uji {
namespace {

using namespace locus;
using namespace locus::tools;
namespace uji = locus::datasets::uji;

struct Args {
    ServerArgs server;
    std::string map = "UJIIndoorLoc";
    std::string file;
    int concurrency = 4;
    std::optional<std::size_t> stop_after;
    bool progress = true;
};

struct Extent {
    double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
    void add(double x, double y) {
        xmin = std::min(xmin, x), ymin = std::min(ymin, y), xmax = std::max(xmax, x), ymax = std::max(ymax, y);
    }
};

std::string fixed(double v, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

void run(const Args& a) {
    const std::string bytes = read_file(a.file);
    const uji::Data data = uji::parse(bytes);
    const auto groups = uji::group_reference_points(data);
    const std::string upload_id = "uji-" + fingerprint(bytes);

    std::map<int, Extent> extent;
    for (const auto& row : data.rows) extent[row.building].add(row.longitude, row.latitude);

    const auto options = a.server.client_options();
    api::Client client(options);
    const auto map = client.ensure_map(a.map, "Imported from the UJIIndoorLoc training CSV (Torres-Sospedra et al., 2014)");

    std::map<int, api::BuildingInfo> buildings;
    std::map<std::pair<int, int>, std::int64_t> radiomap_of;  // (building, floor) -> radio map id
    nlohmann::json radiomap_list = nlohmann::json::array();
    nlohmann::json origins = nlohmann::json::object();
    for (const auto& g : groups) {
        const Extent& e = extent.at(g.building);
        if (!buildings.count(g.building)) {
            const std::string origin = fixed(e.xmin, 4) + "," + fixed(e.ymin, 4);
            buildings[g.building] = client.ensure_building(
                map.id, "Building " + std::to_string(g.building),
                "UJIIndoorLoc BUILDINGID " + std::to_string(g.building) + "; utm_origin=" + origin +
                    " (x = LONGITUDE - X0, y = LATITUDE - Y0)");
            origins[std::to_string(g.building)] = {{"x0", e.xmin}, {"y0", e.ymin}, {"building_id", buildings[g.building].id}};
        }
        const auto key = std::pair{g.building, g.floor};
        if (!radiomap_of.count(key)) {
            api::FloorInfo f;
            f.building_id = buildings[g.building].id;
            f.name = "Floor " + std::to_string(g.floor);
            f.level = g.floor;
            f.width = e.xmax - e.xmin + 1.0;
            f.height = e.ymax - e.ymin + 1.0;
            const auto floor = client.ensure_floor(f);
            // Thirteen radio maps: each name says which building and floor it covers.
            const std::string name = "UJIIndoorLoc building " + std::to_string(g.building) + " floor " + std::to_string(g.floor);
            radiomap_of[key] = client.ensure_radiomap(floor.id, name, "training RPs: mean/variance/count per WAP").id;
            radiomap_list.push_back({{"id", radiomap_of[key]}, {"name", name}, {"building", buildings[g.building].name},
                                     {"building_id", f.building_id}, {"floor", f.name}, {"floor_id", floor.id}});
        }
    }

    // Distinct coordinates can print alike at 0.1 mm: such groups share one RP and one job,
    // so one upload id never covers two jobs for the same RP.
    std::vector<RpJob> jobs;
    std::map<std::pair<std::int64_t, std::string>, std::size_t> job_of;
    for (const auto& g : groups) {
        const Extent& e = extent.at(g.building);
        const std::int64_t rm = radiomap_of.at({g.building, g.floor});
        const std::string name = "b" + std::to_string(g.building) + "f" + std::to_string(g.floor) + "_" +
                                 fixed(g.longitude, 4) + "_" + fixed(g.latitude, 4);
        auto [it, fresh] = job_of.try_emplace({rm, name}, jobs.size());
        if (fresh) {
            RpJob job;
            job.radiomap_id = rm;
            job.name = name;
            job.at = Point{g.longitude - e.xmin, g.latitude - e.ymin};
            job.upload_id = upload_id;
            job.source = a.file;
            jobs.push_back(std::move(job));
        }
        for (auto r : g.rows) jobs[it->second].scans.push_back(uji::scan_of(data, data.rows[r]));
    }

    UploadOptions uo;
    uo.concurrency = a.concurrency;
    uo.stop_after = a.stop_after;
    uo.progress = a.progress && isatty(2);
    const auto summary = upload_rps(options, jobs, uo);
    nlohmann::json out = summary.to_json();
    out["map_id"] = map.id;
    out["buildings"] = buildings.size();
    out["radiomaps"] = radiomap_of.size();
    out["radiomap_list"] = radiomap_list;
    out["rows"] = data.rows.size();
    out["upload_id"] = upload_id;
    out["origins"] = origins;
    std::cout << out.dump() << "\n";
    print_radiomaps(radiomap_list);
    for (const auto& f : summary.failures) std::cerr << "locus: " << f << "\n";
    if (summary.failed > 0) throw CommandError(std::to_string(summary.failed) + " RPs failed to upload; re-run to retry them");
    if (summary.interrupted) throw CommandError("stopped after " + std::to_string(*a.stop_after) + " RPs (--stop-after)", 3);
}

}  // namespace

LOCUS_COMMAND("import-uji", [](CLI::App& app) {
    auto& import = locus::tools::group(app, "import", "Import radio maps from other systems' data through the server API");
    auto* cmd = import.add_subcommand("uji", "Import the UJIIndoorLoc training CSV (one RP per distinct position)");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--map", args->map, "map name (created if missing)")->capture_default_str();
    cmd->add_option("--concurrency", args->concurrency, "parallel connections")->capture_default_str()->check(CLI::Range(1, 64));
    cmd->add_option("--stop-after", args->stop_after, "upload only the first N RPs, then stop (to test resuming)")->group("");
    locus::tools::add_no_progress_flag(*cmd, args->progress);
    cmd->add_option("FILE", args->file, "trainingData.csv")->required()->check(CLI::ExistingFile);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_import_uji
