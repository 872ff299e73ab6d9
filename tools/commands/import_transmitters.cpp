// `locus import transmitters FILE.csv --server URL --floor ID`: a floor's APs and beacons at
// known positions (tools/transmitter_csv.hpp has the columns). The whole file is read and
// checked (also against the floor's size) before anything is sent; a transmitter the floor
// already has (same type and bssid) is updated in place, so importing the same file twice
// changes nothing the second time.
#include <iostream>
#include <map>
#include <memory>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "locus/radio_map.hpp"
#include "survey_connect.hpp"
#include "transmitter_csv.hpp"

namespace locus_cli_import_transmitters {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;

struct Args {
    ServerArgs server;
    std::int64_t floor = 0;
    std::string file;
};

void run(const Args& a) {
    const auto rows = parse_transmitter_csv(read_file(a.file));
    for (const auto& e : rows.errors) std::cerr << a.file << ": " << e << "\n";
    if (!rows.errors.empty()) throw CommandError("nothing imported: " + std::to_string(rows.errors.size()) + " problem(s) in " + a.file);
    if (rows.bodies.empty()) throw CommandError("no transmitter in " + a.file);

    api::Client client(a.server.client_options());
    const std::string collection = "/v1/floors/" + std::to_string(a.floor) + "/transmitters";
    const json floor = client.get("/v1/floors/" + std::to_string(a.floor));
    const double width = floor.at("width").get<double>(), height = floor.at("height").get<double>();
    // Positions off the floor are refused here, for the whole file, before any write.
    std::size_t off = 0;
    for (std::size_t i = 0; i < rows.bodies.size(); ++i) {
        const double x = rows.bodies[i].at("x").get<double>(), y = rows.bodies[i].at("y").get<double>();
        if (x < 0 || x > width || y < 0 || y > height) {
            std::cerr << a.file << ": line " << rows.lines[i] << ": (" << x << ", " << y << ") is not on floor " << a.floor
                      << " ([0, " << width << "] x [0, " << height << "])\n";
            ++off;
        }
    }
    if (off) throw CommandError("nothing imported: " + std::to_string(off) + " transmitter(s) off the floor");

    std::map<std::string, std::int64_t> existing;  // "type|bssid" (normal form) -> id
    for (const auto& t : client.list_all(collection))
        existing[t.at("type").get<std::string>() + "|" + t.at("bssid").get<std::string>()] = t.at("id").get<std::int64_t>();
    std::int64_t created = 0, updated = 0;
    for (std::size_t i = 0; i < rows.bodies.size(); ++i) {
        const json& body = rows.bodies[i];
        const std::string key = body.at("type").get<std::string>() + "|" + Bssid(body.at("bssid").get<std::string>()).str();
        try {
            if (const auto it = existing.find(key); it != existing.end()) {
                client.patch("/v1/transmitters/" + std::to_string(it->second), body);
                ++updated;
            } else {
                existing[key] = client.post(collection, body).at("id").get<std::int64_t>();
                ++created;
            }
        } catch (const api::ApiError& e) {
            throw CommandError(a.file + ": line " + std::to_string(rows.lines[i]) + ": " + plain_numbers(e.what()) + " (" +
                               std::to_string(created) + " created and " + std::to_string(updated) + " updated before it)");
        }
    }
    json out = {{"floor_id", a.floor}, {"created", created}, {"updated", updated}};
    std::cout << out.dump() << "\n";
}

}  // namespace

LOCUS_COMMAND("import-transmitters", [](CLI::App& app) {
    auto& import = locus::tools::group(app, "import", "Import radio maps from other systems' data through the server API");
    auto* cmd = import.add_subcommand("transmitters", "Import a floor's WiFi APs and BLE beacons at known positions from CSV");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--floor", args->floor, "floor id")->required()->check(CLI::PositiveNumber);
    cmd->add_option("FILE", args->file,
                    "CSV with a header: name,type,bssid,x,y,z,tx_power,path_loss_exponent,wall_attenuation "
                    "(or uuid,major,minor / namespace,instance for beacons)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_import_transmitters
