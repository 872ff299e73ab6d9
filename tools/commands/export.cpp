// `locus export --server URL --radiomap ID --format json|csv`: a radio map as the server's
// locus-radiomap/1 document (json, re-importable with POST /v1/floors/{id}/radiomaps/import)
// or one CSV line per stored measurement: rp,x,y,scans,type,bssid,mean,variance,count.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "survey_connect.hpp"

namespace locus_cli_export {
namespace {

using namespace locus::tools;
using nlohmann::json;

struct Args {
    ServerArgs server;
    std::int64_t radiomap = 0;
    std::string format = "json";
    std::string output;
};

std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

void run(const Args& a) {
    locus::api::Client client(a.server.client_options());
    const json doc = client.export_radiomap(a.radiomap);
    std::string text;
    if (a.format == "json") {
        text = doc.dump(1) + "\n";
    } else {
        text = "rp,x,y,scans,type,bssid,mean,variance,count\n";
        for (const auto& rp : doc.at("rps")) {
            const std::string head = csv_field(rp.at("name").get<std::string>()) + "," + number(rp.at("x").get<double>()) + "," +
                                     number(rp.at("y").get<double>()) + "," + std::to_string(rp.value("scans", 0)) + ",";
            for (const auto& m : rp.at("measurements"))
                text += head + m.at("type").get<std::string>() + "," + csv_field(m.at("bssid").get<std::string>()) + "," +
                        number(m.at("mean").get<double>()) + "," + number(m.at("variance").get<double>()) + "," +
                        std::to_string(m.at("count").get<long long>()) + "\n";
        }
    }
    if (a.output.empty()) {
        std::cout << text;
    } else {
        std::ofstream out(a.output, std::ios::binary);
        if (!(out << text)) throw CommandError("cannot write '" + a.output + "'");
        // stdout stays free for the data; the summary of what went into the file is on stderr.
        std::size_t measurements = 0;
        for (const auto& rp : doc.at("rps")) measurements += rp.at("measurements").size();
        std::cerr << "wrote radio map " << a.radiomap << ": " << doc.at("rps").size() << " RPs, " << measurements
                  << " measurements to " << a.output << "\n";
    }
}

}  // namespace

LOCUS_COMMAND("export", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("export", "Export a radio map from the server (json: locus-radiomap/1, or csv)");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--radiomap", args->radiomap, "radio map id")->required();
    cmd->add_option("--format", args->format, "json or csv")->capture_default_str()->check(CLI::IsMember({"json", "csv"}));
    cmd->add_option("--output,-o", args->output, "file to write (default: stdout)");
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_export
