// `locus tune --server URL --radiomap ID [--folds K] [--json]`: asks
// POST /v1/radiomaps/{id}/tune, which cross-validates the radio map's RPs over a grid of
// matcher settings and stores the best as the radio map's own. The endpoint answers when it
// is done (seconds; under a minute on the UJIIndoorLoc map), so the progress shown is a
// spinner with the time elapsed on stderr; then the CV table, best marked, on stdout.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <future>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "survey_connect.hpp"

namespace locus_cli_tune {
namespace {

using namespace locus::tools;
using nlohmann::json;

struct Args {
    ServerArgs server;
    std::int64_t radiomap = 0;
    int folds = 0;  // 0: the server's
    bool as_json = false;
    bool progress = true;
};

void print_table(const json& r) {
    const auto& t = r.at("tune");
    std::printf("radio map %lld: %lld RPs, %lld-fold CV, %lld held-out RPs localized%s, %.1f s\n",
                r.at("radiomap_id").get<long long>(), t.at("rps").get<long long>(), t.at("folds").get<long long>(),
                t.at("queries").get<long long>(), t.at("subsampled").get<bool>() ? " (a subsample)" : "",
                t.at("seconds").get<double>());
    std::printf("  %-32s %10s %12s %8s %9s\n", "candidate", "mean_m", "horizontal_m", "floor", "building");
    const auto chosen = t.at("chosen").get<std::size_t>();
    for (std::size_t i = 0; i < t.at("candidates").size(); ++i) {
        const auto& c = t.at("candidates")[i];
        std::printf("%s %-32s %10.2f %12.2f %7.1f%% %8.1f%%\n", i == chosen ? "*" : " ",
                    c.at("name").get<std::string>().c_str(), c.at("mean_error_m").get<double>(),
                    c.at("mean_horizontal_error_m").get<double>(), 100.0 * c.at("floor_hit_rate").get<double>(),
                    100.0 * c.at("building_hit_rate").get<double>());
    }
    std::printf("stored: %s (* above); localize requests on this radio map now default to it\n",
                r.at("settings").at("algorithm").get<std::string>().c_str());
}

void run(const Args& a) {
    auto options = a.server.client_options();
    // The server answers when the CV is done: give it well over the minute it may take.
    options.read_timeout = std::max(options.read_timeout, std::chrono::milliseconds(180000));
    const json body = a.folds > 0 ? json{{"folds", a.folds}} : json::object();
    const std::string path = "/v1/radiomaps/" + std::to_string(a.radiomap) + "/tune";
    auto call = std::async(std::launch::async, [options, body, path] {
        locus::api::Client client(options);
        return client.post(path, body);
    });
    const bool spin = a.progress && isatty(STDERR_FILENO);
    const auto t0 = std::chrono::steady_clock::now();
    const char frames[] = "|/-\\";
    for (int i = 0; call.wait_for(std::chrono::milliseconds(200)) != std::future_status::ready; ++i) {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (spin) std::fprintf(stderr, "\rtuning radio map %lld %c %.0f s", static_cast<long long>(a.radiomap), frames[i % 4], s);
        else if (a.progress && i > 0 && i % 25 == 0)
            std::fprintf(stderr, "tuning radio map %lld: %.0f s\n", static_cast<long long>(a.radiomap), s);
    }
    if (spin) std::fprintf(stderr, "\r%60s\r", "");
    json r;
    try {
        r = call.get();
    } catch (const locus::api::ApiError& e) {
        throw CommandError("tune of radio map " + std::to_string(a.radiomap) + " refused (" + e.code() + "): " + e.what());
    }
    if (a.as_json) {
        std::cout << r.dump(1) << "\n";
        return;
    }
    print_table(r);
}

}  // namespace

LOCUS_COMMAND("tune", [](CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "tune", "Let a radio map choose its own matcher settings by cross-validation over its RPs, and show the table");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--radiomap", args->radiomap, "radio map id")->required()->check(CLI::PositiveNumber);
    cmd->add_option("--folds", args->folds, "K of the K-fold CV (default: the server's, 10)")->check(CLI::Range(2, 50));
    cmd->add_flag("--json", args->as_json, "print the server's answer as JSON");
    add_no_progress_flag(*cmd, args->progress);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_tune
