// `locus plan …`: a floor's plan as a GeoJSON file.
//   from-image PLAN.png --px-per-m S [--out FILE]   walls and free space from a drawing
//   import FILE.geojson --floor ID                  checked here, then PUT /v1/floors/{id}/plan
//   export --floor ID [--out FILE]                  GET /v1/floors/{id}/plan; import takes it back
#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "image_file.hpp"
#include "locus/plan/geojson.hpp"
#include "locus/imaging/plan_from_image.hpp"
#include "locus/plan/check.hpp"
#include "plan_remap.hpp"
#include "survey_connect.hpp"

namespace locus_cli_plan {
namespace {

using namespace locus::tools;
using nlohmann::json;

void write_text(const std::string& text, const std::string& out) {
    if (out.empty()) {
        std::cout << text;
        return;
    }
    std::ofstream f(out, std::ios::binary);
    if (!(f << text)) throw CommandError("cannot write '" + out + "'");
}

// A plan's problems as the server would list them, so a file is fixed before it is sent.
std::string problems_text(const std::vector<locus::plan::PlanProblem>& problems) {
    std::string text;
    for (std::size_t i = 0; i < problems.size() && i < 20; ++i)
        text += "\n  " + problems[i].feature + ": " + problems[i].problem;
    if (problems.size() > 20) text += "\n  and " + std::to_string(problems.size() - 20) + " more";
    return text;
}

struct FromImageArgs {
    std::string image;
    locus::imaging::FromImageOptions options;
    std::string out;
};

void from_image(const FromImageArgs& a) {
    const auto image = read_grey_image(a.image);
    locus::imaging::FromImageStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    locus::plan::Plan plan;
    try {
        plan = locus::imaging::plan_from_image(image, a.options, &stats);
    } catch (const std::invalid_argument& e) {
        throw CommandError(e.what());
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (const auto problems = locus::plan::check_plan(plan); !problems.empty())
        throw CommandError("the plan made from '" + a.image + "' fails its checks (please report it):" + problems_text(problems));
    write_text(locus::plan::to_geojson(plan).dump(1) + "\n", a.out);
    // stdout holds the document; what went into it is on stderr.
    char line[256];
    std::snprintf(line, sizeof line,
                  "%s: %d × %d px = %.1f m × %.1f m; %zu walls (%zu points), %zu spaces (%zu points, %zu holes) in %.2f s\n",
                  a.image.c_str(), image.width, image.height, image.width / a.options.px_per_m,
                  image.height / a.options.px_per_m, stats.walls, stats.wall_points, stats.spaces, stats.space_points,
                  stats.holes, seconds);
    std::cerr << line;
    if (stats.spaces == 0)
        std::cerr << "no enclosed space was found: are the outer walls drawn, or do gaps wider than --close-m "
                     "let the outside in?\n";
}

// The file as the codec reads it, or an error naming the feature at fault.
locus::plan::Plan read_plan_file(const std::string& path, json& doc) {
    doc = json::parse(read_file(path), nullptr, false);
    if (doc.is_discarded()) throw CommandError("'" + path + "' is not JSON");
    locus::plan::Plan plan;
    try {
        plan = locus::plan::from_geojson(doc);
    } catch (const locus::plan::GeoJsonError& e) {
        throw CommandError("'" + path + "' is not a plan: " + e.what());
    }
    if (const auto problems = locus::plan::check_plan(plan); !problems.empty())
        throw CommandError("'" + path + "' is not a plan the server takes:" + problems_text(problems));
    return plan;
}

struct ImportArgs {
    ServerArgs server;
    std::string file;
    std::int64_t floor = 0;
};

// The ids the target floor has, for remap_plan.
FloorIds floor_ids(locus::api::Client& client, std::int64_t floor_id) {
    FloorIds ids;
    ids.floor_id = floor_id;
    const auto floor = client.floor(floor_id);
    for (const auto& r : client.rooms(floor_id)) ids.rooms.insert(r.id);
    for (const auto& p : client.pois(floor_id)) ids.pois.insert(p.id);
    const auto map_id = client.get("/v1/buildings/" + std::to_string(floor.building_id)).at("map_id").get<std::int64_t>();
    for (const auto& b : client.buildings(map_id))
        for (const auto& f : client.floors(b.id)) ids.map_floors.insert(f.id);
    return ids;
}

void import_plan(const ImportArgs& a) {
    json doc;
    auto plan = read_plan_file(a.file, doc);
    locus::api::Client client(a.server.client_options());
    // A plan exported from another floor links that floor's rooms and POIs: dropped, so the
    // rooms are matched by name here instead.
    RemapReport remap;
    try {
        remap = remap_plan(plan, floor_ids(client, a.floor));
    } catch (const locus::api::ApiError& e) {
        throw CommandError("the server refused the plan of floor " + std::to_string(a.floor) + " (" + e.code() + "): " +
                           e.what());
    }
    if (remap.changed()) {
        std::cerr << a.file << ": made for another floor: " << remap.room_links_dropped << " room links and "
                  << remap.poi_links_dropped << " POI links dropped (rooms are matched by name on floor " << a.floor
                  << ", or made)";
        for (const auto& l : remap.floor_links_dropped) std::cerr << "; dropped the link of " << l << " (not another floor of this map)";
        std::cerr << "\n";
    }
    json stored;
    try {
        stored = client.put("/v1/floors/" + std::to_string(a.floor) + "/plan", locus::plan::to_geojson(plan));
    } catch (const locus::api::ApiError& e) {
        throw CommandError("the server refused the plan of floor " + std::to_string(a.floor) + " (" + e.code() + "): " +
                           e.what());
    }
    std::cerr << "floor " << a.floor << ": plan version " << stored.value("version", 0) << " stored ("
              << plan.spaces.size() << " spaces, " << plan.walls.size() << " walls, " << plan.doors.size() << " doors, "
              << plan.connectors.size() << " connectors)\n";
}

struct ExportArgs {
    ServerArgs server;
    std::int64_t floor = 0;
    std::string out;
};

void export_plan(const ExportArgs& a) {
    locus::api::Client client(a.server.client_options());
    json stored;
    try {
        stored = client.get("/v1/floors/" + std::to_string(a.floor) + "/plan");
    } catch (const locus::api::ApiError& e) {
        throw CommandError("cannot export the plan of floor " + std::to_string(a.floor) + " (" + e.code() + "): " + e.what());
    }
    write_text(stored.dump(1) + "\n", a.out);
    if (!a.out.empty())
        std::cerr << "wrote the plan of floor " << a.floor << " (version " << stored.value("version", 0) << ", "
                  << stored.value("features", json::array()).size() << " features) to " << a.out << "\n";
}

}  // namespace

LOCUS_COMMAND("plan", [](CLI::App& app) {
    auto& plan = group(app, "plan", "Floor plans as GeoJSON: from a drawing, to and from the server");

    auto* img = plan.add_subcommand("from-image", "Walls and walkable space from a plan drawing (PNG or JPEG), as GeoJSON");
    auto fa = std::make_shared<FromImageArgs>();
    img->add_option("image", fa->image, "the drawing: PNG or JPEG")->required()->check(CLI::ExistingFile);
    img->add_option("--px-per-m", fa->options.px_per_m, "the drawing's scale: pixels per metre")
        ->required()
        ->check(CLI::PositiveNumber);
    img->add_option("--threshold", fa->options.threshold, "grey level (0-255) below which a pixel is a wall's ink")
        ->capture_default_str()
        ->check(CLI::Range(1, 255));
    img->add_option("--close-m", fa->options.close_m,
                    "gaps in the outer walls up to this many metres (entrances, windows) are closed to find the inside")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    img->add_option("--simplify-m", fa->options.simplify_m, "how far (m) a simplified outline may stray from the drawing")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    img->add_option("--merge-m", fa->options.merge_m, "strokes closer than this (m) become one wall")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    img->add_option("--min-wall-m", fa->options.min_wall_m, "strokes shorter than this (m) are dropped as text or marks")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    img->add_option("--out,-o", fa->out, "file to write (default: stdout)");
    img->callback([fa] { from_image(*fa); });

    auto* imp = plan.add_subcommand("import", "Check a GeoJSON plan and store it as a floor's plan (PUT)");
    auto ia = std::make_shared<ImportArgs>();
    ia->server.add_to(*imp);
    imp->add_option("file", ia->file, "the plan: a GeoJSON FeatureCollection in floor metres")->required()->check(CLI::ExistingFile);
    imp->add_option("--floor", ia->floor, "floor id")->required()->check(CLI::PositiveNumber);
    imp->callback([ia] { import_plan(*ia); });

    auto* exp = plan.add_subcommand("export", "A floor's stored plan as GeoJSON (plan import takes it back)");
    auto ea = std::make_shared<ExportArgs>();
    ea->server.add_to(*exp);
    exp->add_option("--floor", ea->floor, "floor id")->required()->check(CLI::PositiveNumber);
    exp->add_option("--out,-o", ea->out, "file to write (default: stdout)");
    exp->callback([ea] { export_plan(*ea); });
});

}  // namespace locus_cli_plan
