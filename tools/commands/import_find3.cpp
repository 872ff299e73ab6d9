// `locus import find3 --server URL --map NAME FILE.jsons`: FIND3 fingerprints into a map.
// FIND3 labels locations symbolically, so each label becomes a square room of --room-size
// metres, laid side by side along x in label order on one floor, and one RP at the room's
// centre holding every scan of that label. Upload ids come from the file's content hash:
// re-importing the same file changes no count.
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/survey_sources.hpp"
#include "survey_connect.hpp"
#include "survey_upload.hpp"

namespace locus_cli_import_find3 {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;

struct Args {
    ServerArgs server;
    std::string map = "FIND3";
    std::string building;
    std::string file;
    double room_size = 5.0;
    bool progress = true;
};

void run(const Args& a) {
    const std::string bytes = read_file(a.file);
    const auto data = datasets::survey::parse_find3(bytes);
    for (const auto& e : data.errors) std::cerr << a.file << ":" << e.line << ": " << e.message << "\n";
    if (data.by_label.empty()) throw CommandError("no usable fingerprint in " + a.file);

    const auto options = a.server.client_options();
    api::Client client(options);
    const auto map = client.ensure_map(a.map, "Imported from FIND3 fingerprints");
    const std::string building_name = !a.building.empty() ? a.building : (data.family.empty() ? "find3" : data.family);
    const auto building = client.ensure_building(map.id, building_name, "FIND3 family " + data.family);
    api::FloorInfo f;
    f.building_id = building.id;
    f.name = "Floor 0";
    f.width = a.room_size * static_cast<double>(data.by_label.size());
    f.height = a.room_size;
    const auto floor = client.ensure_floor(f);
    const auto radiomap = client.ensure_radiomap(floor.id, "find3", "one RP per FIND3 location label, at its room's centre");

    std::map<std::string, std::int64_t> rooms;
    for (const auto& r : client.rooms(floor.id)) rooms[r.name] = r.id;
    const std::string upload_id = "find3-" + fingerprint(bytes);
    std::vector<RpJob> jobs;
    std::size_t i = 0, rooms_created = 0;
    for (const auto& [label, scans] : data.by_label) {
        const Rect rect{a.room_size * static_cast<double>(i), 0.0, a.room_size * static_cast<double>(i + 1), a.room_size};
        ++i;
        if (!rooms.count(label)) {
            client.create_room({{0, label, {rect}}, floor.id});
            ++rooms_created;
        }
        RpJob job;
        job.radiomap_id = radiomap.id;
        job.name = label;
        job.at = rect.centre();
        job.scans = scans;
        job.upload_id = upload_id;
        job.source = a.file;
        jobs.push_back(std::move(job));
    }
    UploadOptions uo;
    uo.progress = a.progress && isatty(2);
    const auto summary = upload_rps(options, jobs, uo);
    json out = summary.to_json();
    out["map_id"] = map.id;
    out["floor_id"] = floor.id;
    out["radiomap_id"] = radiomap.id;
    out["rooms_created"] = rooms_created;
    out["malformed_lines"] = data.errors.size();
    out["upload_id"] = upload_id;
    std::cout << out.dump() << "\n";
    for (const auto& fl : summary.failures) std::cerr << "locus: " << fl << "\n";
    if (summary.failed > 0) throw CommandError(std::to_string(summary.failed) + " RPs failed to upload; re-run to retry them");
}

}  // namespace

LOCUS_COMMAND("import-find3", [](CLI::App& app) {
    auto& import = locus::tools::group(app, "import", "Import radio maps from other systems' data through the server API");
    auto* cmd = import.add_subcommand("find3", "Import FIND3 fingerprints (one room and one RP per location label)");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--map", args->map, "map name (created if missing)")->capture_default_str();
    cmd->add_option("--building", args->building, "building name (default: the FIND3 family)");
    cmd->add_option("--room-size", args->room_size, "side of each label's square room, metres")
        ->capture_default_str()
        ->check(CLI::Range(0.5, 1000.0));
    locus::tools::add_no_progress_flag(*cmd, args->progress);
    cmd->add_option("FILE", args->file, "FIND3 .jsons export")->required()->check(CLI::ExistingFile);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_import_find3
