// `locus route --server URL --map ID --from PLACE --to PLACE [--step-free] [--avoid ROOM_ID,…]`:
// asks POST /v1/maps/{id}/route and prints the instructions, numbered, then the length and
// time (--json: the server's answer as it is). PLACE is room:ID, poi:ID or FLOOR_ID:X,Y.
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "route_place.hpp"
#include "survey_connect.hpp"

namespace locus_cli_route {
namespace {

using namespace locus::tools;
using nlohmann::json;

struct Args {
    ServerArgs server;
    std::int64_t map = 0;
    std::string from, to;
    bool step_free = false;
    std::vector<std::int64_t> avoid;
    double walking_speed = 0.0;  // 0: the server's default
    bool as_json = false;
};

std::string format(const char* fmt, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

void run(const Args& a) {
    json body = {{"from", place_json(a.from, "--from")}, {"to", place_json(a.to, "--to")}};
    json options = json::object();
    if (a.step_free) options["step_free"] = true;
    if (!a.avoid.empty()) options["avoid"] = a.avoid;
    if (a.walking_speed > 0.0) options["walking_speed"] = a.walking_speed;
    if (!options.empty()) body["options"] = options;

    locus::api::Client client(a.server.client_options());
    json r;
    try {
        r = client.post("/v1/maps/" + std::to_string(a.map) + "/route", body);
    } catch (const locus::api::ApiError& e) {
        if (e.code() == "no_route") throw CommandError("no route: " + std::string(e.what()), 2);
        throw CommandError("route on map " + std::to_string(a.map) + " refused (" + e.code() + "): " + e.what());
    }
    if (a.as_json) {
        std::cout << r.dump(1) << "\n";
        return;
    }
    int n = 0;
    for (const auto& step : r.at("steps")) std::cout << ++n << ". " << step.at("text").get<std::string>() << "\n";
    const double t = r.at("time_s").get<double>();
    std::cout << "total: " << format("%.0f m", r.at("length_m").get<double>()) << ", about "
              << (t < 90.0 ? format("%.0f s", t) : format("%.1f min", t / 60.0)) << "\n";
}

}  // namespace

LOCUS_COMMAND("route", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("route", "Directions between two places of a map, through its floor plans");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--map", args->map, "map id")->required()->check(CLI::PositiveNumber);
    cmd->add_option("--from", args->from, "start: room:ID, poi:ID or FLOOR_ID:X,Y (metres)")->required();
    cmd->add_option("--to", args->to, "destination: room:ID, poi:ID or FLOOR_ID:X,Y (metres)")->required();
    cmd->add_flag("--step-free", args->step_free, "no stairs or escalators");
    cmd->add_option("--avoid", args->avoid, "room ids to keep out of, comma-separated")->delimiter(',');
    cmd->add_option("--walking-speed", args->walking_speed, "m/s (default: the server's, 1.3)")->check(CLI::Range(0.1, 10.0));
    cmd->add_flag("--json", args->as_json, "print the server's answer as JSON");
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_route
