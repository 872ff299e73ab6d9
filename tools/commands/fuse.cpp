// `locus fuse`: one fusion step of docs/spec.md §6 by hand, e.g.
//   locus fuse --rule proportional --pdr 3,0 --wifi 0,4 --prev 0,0 --aps 5
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "command_registry.hpp"
#include "locus/motion/fusion/rules.hpp"

namespace locus_cli_fuse {
namespace {

using namespace locus;

Point parse_point(const std::string& text, const char* what) {
    const auto comma = text.find(',');
    try {
        if (comma == std::string::npos) throw std::invalid_argument("no comma");
        std::size_t used_x = 0, used_y = 0;
        const std::string xs = text.substr(0, comma), ys = text.substr(comma + 1);
        const Point p{std::stod(xs, &used_x), std::stod(ys, &used_y)};
        if (used_x != xs.size() || used_y != ys.size()) throw std::invalid_argument("trailing characters");
        return p;
    } catch (const std::exception&) {
        throw tools::CommandError(std::string(what) + " must be X,Y in metres, got '" + text + "'");
    }
}

struct Args {
    std::string rule, pdr, wifi, prev, prev_wifi;
    int aps = 0;
    fusion::RuleParams params;
};

void run(const Args& a) {
    const auto rule = fusion::parse_rule(a.rule);
    if (!rule)
        throw tools::CommandError("unknown --rule '" + a.rule +
                                  "' (only_wifi, midpoint, midpoint_threshold, proportional, proportional2)");
    fusion::FusionInput in;
    in.pdr = parse_point(a.pdr, "--pdr");
    in.wifi = parse_point(a.wifi, "--wifi");
    if (!a.prev.empty()) in.prev = parse_point(a.prev, "--prev");
    if (!a.prev_wifi.empty()) in.prev_wifi = parse_point(a.prev_wifi, "--prev-wifi");
    in.aps = a.aps;
    Point out;
    try {
        out = fusion::fuse(*rule, in, a.params);
    } catch (const std::invalid_argument& e) {
        throw tools::CommandError(e.what());
    }
    std::cout << nlohmann::json{{"x", out.x}, {"y", out.y}}.dump() << "\n";
}

}  // namespace

LOCUS_COMMAND("fuse", [](CLI::App& app) {
    auto args = std::make_shared<Args>();
    auto* cmd = app.add_subcommand("fuse", "One fusion step of a PDR position and a WiFi fix; prints {\"x\", \"y\"}");
    cmd->add_option("--rule", args->rule, "only_wifi, midpoint, midpoint_threshold, proportional, proportional2")
        ->required();
    cmd->add_option("--pdr", args->pdr, "PDR position X,Y")->required();
    cmd->add_option("--wifi", args->wifi, "WiFi fix X,Y")->required();
    cmd->add_option("--prev", args->prev, "Previous fused position X,Y (omit for the first fix: the fix is taken)");
    cmd->add_option("--aps", args->aps, "APs in the online scan (N)")->required();
    cmd->add_option("--prev-wifi", args->prev_wifi, "Previous WiFi fix X,Y (proportional2: same fix twice keeps PDR)");
    cmd->add_option("--lambda", args->params.lambda_m, "midpoint_threshold λ in metres (default 4)");
    cmd->add_option("--nmax", args->params.n_max, "proportional N_max (default 10)");
    cmd->add_option("--gamma", args->params.gamma, "proportional γ, natural number (default 2)");
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_fuse
