// `locus import putmc DIR --server URL --map NAME`: the PUTMC floor (../shared/data/README.md)
// into a map through the public API: building "PUTMC", floor "Floor 3" sized from the plan
// image and map/scale.map, the image uploaded with its placement (its bottom-left corner at the
// floor's origin, metres per pixel = 1 / scale), the floor plan made from the image as
// `locus plan from-image` makes it (walls for map matching), and radio map "PUTMC survey" with
// one RP per surveyed point ("p<id>", one scan each).
//
// Coordinates: PUTMC's y runs down the image, a floor's up: y_floor = height − y
// (putmc::to_floor), the one flip `locus eval walks` applies to the walks' ground truth too.
//
// Re-runnable: hierarchy found by name, the image and plan replaced by the same ones, and
// every RP upload carries upload_id "putmc-<content hash of map/wifi.map>".
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <unistd.h>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/putmc.hpp"
#include "image_file.hpp"
#include "locus/api/client.hpp"
#include "locus/imaging/plan_from_image.hpp"
#include "survey_connect.hpp"
#include "survey_upload.hpp"

namespace locus_cli_import_putmc {
namespace {

using namespace locus;
using namespace locus::tools;
namespace putmc = locus::datasets::putmc;

struct Args {
    ServerArgs server;
    std::string map = "PUTMC";
    std::string dir;
    bool plan = true;
    int concurrency = 4;
    bool progress = true;
};

std::string map_dir(const std::string& dir) {
    namespace fs = std::filesystem;
    if (fs::exists(fs::path(dir) / "map" / "wifi.map")) return (fs::path(dir) / "map").string();
    if (fs::exists(fs::path(dir) / "wifi.map") && fs::exists(fs::path(dir) / "scale.map")) return dir;
    throw CommandError("'" + dir + "' holds neither map/wifi.map nor wifi.map and scale.map: is it the PUTMC directory?");
}

// PUT /v1/floors/{id}/image: the client library has no image call (only this command sends one).
nlohmann::json put_image(const ServerArgs& server, std::int64_t floor_id, const std::string& bytes, double metres_per_pixel) {
    httplib::Client http(server.client_options().base_url);
    http.set_read_timeout(static_cast<time_t>(server.timeout_s));
    httplib::Headers headers;
    if (!server.api_key.empty()) headers.emplace("Authorization", "Bearer " + server.api_key);
    char query[64];
    std::snprintf(query, sizeof query, "?metres_per_pixel=%.12g", metres_per_pixel);
    const auto path = "/v1/floors/" + std::to_string(floor_id) + "/image" + query;
    const auto res = http.Put(path, headers, bytes, "image/png");
    if (!res) throw CommandError("PUT " + path + ": " + httplib::to_string(res.error()));
    if (res->status / 100 != 2) throw CommandError("PUT " + path + ": HTTP " + std::to_string(res->status) + " " + res->body);
    return nlohmann::json::parse(res->body, nullptr, false);
}

void run(const Args& a) {
    const std::string mdir = map_dir(a.dir);
    putmc::Survey survey;
    try {
        survey = putmc::read_survey(mdir);
    } catch (const std::runtime_error& e) {
        throw CommandError(e.what());
    }
    const std::string image_path = (std::filesystem::path(mdir) / "floorplan.png").string();
    const auto image = read_grey_image(image_path);
    const double width_m = image.width / survey.px_per_m, height_m = image.height / survey.px_per_m;

    const auto options = a.server.client_options();
    api::Client client(options);
    const auto map = client.ensure_map(a.map, "PUTMC floor 3 (Nowicki & Skrzypczyński, Sensors 2019): survey and plan image");
    const auto building = client.ensure_building(map.id, "PUTMC", "Poznan University of Technology, floor 3 of the PUTMC data set");
    api::FloorInfo f;
    f.building_id = building.id;
    f.name = "Floor 3";
    f.level = 3;
    f.width = width_m;
    f.height = height_m;
    const auto floor = client.ensure_floor(f);
    if (std::abs(floor.height - height_m) > 1e-6 || std::abs(floor.width - width_m) > 1e-6)
        throw CommandError("floor " + std::to_string(floor.id) + " exists with another size (" + std::to_string(floor.width) +
                           " × " + std::to_string(floor.height) + " m, the image gives " + std::to_string(width_m) + " × " +
                           std::to_string(height_m) + "): the survey's points would not land on the drawing");
    const auto placement = put_image(a.server, floor.id, read_file(image_path), 1.0 / survey.px_per_m);

    std::size_t walls = 0;
    if (a.plan) {
        imaging::FromImageOptions io;
        io.px_per_m = survey.px_per_m;
        const auto stored = client.put_plan(floor.id, imaging::plan_from_image(image, io));
        walls = stored.walls.size();
    }

    const auto rm = client.ensure_radiomap(floor.id, "PUTMC survey", "one scan at each of the surveyed points (map/wifi.map)");
    const std::string upload_id = "putmc-" + fingerprint(read_file((std::filesystem::path(mdir) / "wifi.map").string()));
    std::vector<RpJob> jobs;
    for (const auto& s : survey.scans) {
        const std::string name = "p" + std::to_string(s.loc_id);
        auto it = std::find_if(jobs.begin(), jobs.end(), [&](const RpJob& j) { return j.name == name; });
        if (it == jobs.end()) {
            RpJob job;
            job.radiomap_id = rm.id;
            job.name = name;
            job.at = putmc::to_floor(survey.at_of(s.loc_id), height_m);
            job.upload_id = upload_id;
            job.source = mdir + "/wifi.map";
            jobs.push_back(std::move(job));
            it = jobs.end() - 1;
        }
        if (!s.readings.empty()) it->scans.push_back(s.readings);
    }
    std::erase_if(jobs, [](const RpJob& j) { return j.scans.empty(); });

    UploadOptions uo;
    uo.concurrency = a.concurrency;
    uo.progress = a.progress && isatty(2);
    const auto summary = upload_rps(options, jobs, uo);
    nlohmann::json out = summary.to_json();
    out["map_id"] = map.id;
    out["building_id"] = building.id;
    out["floor_id"] = floor.id;
    out["radiomap_id"] = rm.id;
    out["floor_size_m"] = {width_m, height_m};
    out["image"] = placement;
    if (a.plan) out["plan_walls"] = walls;
    out["upload_id"] = upload_id;
    std::cout << out.dump() << "\n";
    print_radiomaps(nlohmann::json::array({{{"id", rm.id}, {"name", rm.name}, {"building", building.name},
                                            {"floor", floor.name}, {"floor_id", floor.id}}}));
    for (const auto& fail : summary.failures) std::cerr << "locus: " << fail << "\n";
    if (summary.failed > 0) throw CommandError(std::to_string(summary.failed) + " RPs failed to upload; re-run to retry them");
}

}  // namespace

LOCUS_COMMAND("import-putmc", [](CLI::App& app) {
    auto& import = locus::tools::group(app, "import", "Import radio maps from other systems' data through the server API");
    auto* cmd = import.add_subcommand("putmc", "Import the PUTMC floor: plan image, plan, and the survey's one-scan RPs");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--map", args->map, "map name (created if missing)")->capture_default_str();
    cmd->add_option("--concurrency", args->concurrency, "parallel connections")->capture_default_str()->check(CLI::Range(1, 64));
    cmd->add_flag_callback("--no-plan", [args] { args->plan = false; }, "do not make and PUT the floor plan from the image");
    locus::tools::add_no_progress_flag(*cmd, args->progress);
    cmd->add_option("DIR", args->dir, "the PUTMC directory (holding map/) or its map/ directory")->required()->check(CLI::ExistingDirectory);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_import_putmc
