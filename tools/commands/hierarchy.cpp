// `locus map create`, `locus building create`, `locus floor create`: a building of your own
// from scratch (docs/your-building.md), without writing JSON by hand. Each prints the created
// object as the server answers it (one JSON line, with its `id`). What is missing is said all
// at once, before anything is sent. `locus map list`, `locus building list --map ID`,
// `locus floor list --building ID`: what there is, as a table (with --json, the server's
// objects as one JSON array), every page of the collection.
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "survey_connect.hpp"

namespace locus_cli_hierarchy {
namespace {

using namespace locus::tools;
using nlohmann::json;

struct Args {
    ServerArgs server;
    std::int64_t parent = 0;
    std::string name, description;
    int level = 0;
    std::optional<double> width, height, north_offset_deg;
    bool json_out = false;  // list: JSON instead of a table
};

// "--width and --height are required" for every option still unset.
void require(const std::vector<std::pair<const char*, bool>>& options) {
    std::vector<std::string> missing;
    for (const auto& [name, given] : options)
        if (!given) missing.emplace_back(name);
    if (missing.empty()) return;
    std::string list;
    for (std::size_t i = 0; i < missing.size(); ++i)
        list += (i == 0 ? "" : i + 1 == missing.size() ? " and " : ", ") + missing[i];
    throw CommandError(list + (missing.size() == 1 ? " is" : " are") + " required", 2);
}

void create(const Args& a, const std::string& path, json body) {
    locus::api::Client client(a.server.client_options());
    if (!a.description.empty()) body["description"] = a.description;
    std::cout << client.post(path, body).dump() << "\n";
}

// `locus GROUP NAME`, with the server's options, its Args in `args`.
CLI::App* command(CLI::App& app, const char* group, const char* name, const char* what, std::shared_ptr<Args>& args) {
    auto& g = locus::tools::group(app, group, std::string("Create and list ") + group + "s");
    auto* cmd = g.add_subcommand(name, what);
    args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    return cmd;
}

CLI::App* subcommand(CLI::App& app, const char* group, const char* what, std::shared_ptr<Args>& args) {
    auto* cmd = command(app, group, "create", what, args);
    cmd->add_option("--name", args->name, "its name (unique among its siblings)");
    return cmd;
}

// A value as a table cell: text as it is, numbers as JSON writes them, nothing for null.
std::string cell(const json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_null()) return "";
    return v.dump();
}

// `list`: every row of `path`, as one JSON array, or a table of `columns` (left-aligned,
// two spaces apart, a header line).
void list(const Args& a, const std::string& path, const std::vector<std::string>& columns) {
    locus::api::Client client(a.server.client_options());
    const std::vector<json> rows = client.list_all(path);
    if (a.json_out) {
        std::cout << json(rows).dump() << "\n";
        return;
    }
    std::vector<std::size_t> width;
    for (const auto& c : columns) width.push_back(c.size());
    for (const auto& r : rows)
        for (std::size_t i = 0; i < columns.size(); ++i) width[i] = std::max(width[i], cell(r.value(columns[i], json())).size());
    const auto line = [&](const auto& text_of) {
        std::string out;
        for (std::size_t i = 0; i < columns.size(); ++i) {
            const std::string t = text_of(i);
            out += i + 1 == columns.size() ? t : t + std::string(width[i] - t.size() + 2, ' ');
        }
        std::cout << out << "\n";
    };
    line([&](std::size_t i) { return columns[i]; });
    for (const auto& r : rows) line([&](std::size_t i) { return cell(r.value(columns[i], json())); });
}

CLI::App* list_subcommand(CLI::App& app, const char* group, const char* what, std::shared_ptr<Args>& args) {
    auto* cmd = command(app, group, "list", what, args);
    cmd->add_flag("--json", args->json_out, "the server's objects as one JSON array instead of a table");
    return cmd;
}

}  // namespace

LOCUS_COMMAND("map-create", [](CLI::App& app) {
    std::shared_ptr<Args> args;
    auto* cmd = subcommand(app, "map", "Create a map (a site: one or more buildings)", args);
    cmd->add_option("--description", args->description, "what it is");
    cmd->callback([args] {
        require({{"--name", !args->name.empty()}});
        create(*args, "/v1/maps", {{"name", args->name}});
    });
});

LOCUS_COMMAND("building-create", [](CLI::App& app) {
    std::shared_ptr<Args> args;
    auto* cmd = subcommand(app, "building", "Create a building of a map", args);
    cmd->add_option("--map", args->parent, "the map's id");
    cmd->add_option("--description", args->description, "what it is");
    cmd->callback([args] {
        require({{"--map", args->parent > 0}, {"--name", !args->name.empty()}});
        create(*args, "/v1/maps/" + std::to_string(args->parent) + "/buildings", {{"name", args->name}});
    });
});

LOCUS_COMMAND("floor-create", [](CLI::App& app) {
    std::shared_ptr<Args> args;
    auto* cmd = subcommand(app, "floor", "Create a floor of a building: a rectangle of --width × --height metres", args);
    cmd->add_option("--building", args->parent, "the building's id");
    cmd->add_option("--level", args->level, "its level (0 the ground floor, -1 below it)")->capture_default_str();
    cmd->add_option("--width", args->width, "metres along x (east-west on a plan drawn north up)")->check(CLI::PositiveNumber);
    cmd->add_option("--height", args->height, "metres along y")->check(CLI::PositiveNumber);
    cmd->add_option("--north-offset", args->north_offset_deg,
                    "degrees from the floor's +y axis to magnetic north, for step headings (docs/pdr.md)")
        ->check(CLI::Range(-360.0, 360.0));
    cmd->callback([args] {
        require({{"--building", args->parent > 0}, {"--name", !args->name.empty()}, {"--width", args->width.has_value()},
                 {"--height", args->height.has_value()}});
        json body = {{"name", args->name}, {"level", args->level}, {"width", *args->width}, {"height", *args->height}};
        if (args->north_offset_deg) body["north_offset_deg"] = *args->north_offset_deg;
        create(*args, "/v1/buildings/" + std::to_string(args->parent) + "/floors", body);
    });
});

LOCUS_COMMAND("map-list", [](CLI::App& app) {
    std::shared_ptr<Args> args;
    auto* cmd = list_subcommand(app, "map", "List the maps", args);
    cmd->callback([args] { list(*args, "/v1/maps", {"id", "name", "description"}); });
});

LOCUS_COMMAND("building-list", [](CLI::App& app) {
    std::shared_ptr<Args> args;
    auto* cmd = list_subcommand(app, "building", "List a map's buildings", args);
    cmd->add_option("--map", args->parent, "the map's id");
    cmd->callback([args] {
        require({{"--map", args->parent > 0}});
        list(*args, "/v1/maps/" + std::to_string(args->parent) + "/buildings", {"id", "name", "description"});
    });
});

LOCUS_COMMAND("floor-list", [](CLI::App& app) {
    std::shared_ptr<Args> args;
    auto* cmd = list_subcommand(app, "floor", "List a building's floors", args);
    cmd->add_option("--building", args->parent, "the building's id");
    cmd->callback([args] {
        require({{"--building", args->parent > 0}});
        list(*args, "/v1/buildings/" + std::to_string(args->parent) + "/floors", {"id", "level", "name", "width", "height"});
    });
});

}  // namespace locus_cli_hierarchy
