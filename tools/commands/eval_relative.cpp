// `locus eval relative [--runs N] [--seed S] [--start-distance M] [--seconds T] [--json]`:
// Bonjorn López 2016's two walkers (sim/two_walkers.hpp): B stands, A walks to find it from PDR and a
// phone-to-phone distance per step; the relative-direction error of the estimator for each way
// of getting that distance. No server: the simulator and client-lib only.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "sim/two_walkers.hpp"

namespace locus_cli_eval_relative {
namespace {

using namespace locus;

struct Args {
    sim::TwoWalkerConfig config;
    std::uint64_t seed = 1;
    int runs = 200;
    bool json = false;
};

void run(const Args& a) {
    nlohmann::json out = nlohmann::json::array();
    if (!a.json)
        std::printf("%-21s %5s %12s %9s %9s %6s %10s %12s\n", "method", "runs", "median_err°", "p90_err°",
                    "coverage", "met", "met_after", "median_|Δd|");
    for (auto m : {sim::RelativeMethod::Rssi, sim::RelativeMethod::RssiMean, sim::RelativeMethod::RssiKalman,
                   sim::RelativeMethod::RssiKalmanAcoustic, sim::RelativeMethod::RssiFit, sim::RelativeMethod::Exact, sim::RelativeMethod::BothFixes}) {
        const auto s = sim::evaluate_two_walkers(a.config, m, a.seed, a.runs);
        if (a.json) {
            out.push_back({{"method", sim::method_name(m)},
                           {"runs", s.runs},
                           {"median_error_deg", s.median_error_deg},
                           {"p90_error_deg", s.p90_error_deg},
                           {"estimate_coverage", s.estimate_coverage},
                           {"met_share", s.met_share},
                           {"median_met_after_s", s.median_met_after_s},
                           {"median_distance_error_m", s.median_distance_error}});
        } else {
            std::printf("%-21s %5d %12.1f %9.1f %8.0f%% %5.0f%% %9.1fs %11.2fm\n", sim::method_name(m), s.runs,
                        s.median_error_deg, s.p90_error_deg, 100.0 * s.estimate_coverage, 100.0 * s.met_share,
                        s.median_met_after_s, s.median_distance_error);
        }
    }
    if (a.json) std::cout << out.dump(1) << "\n";
}

}  // namespace

LOCUS_COMMAND("eval-relative", [](CLI::App& app) {
    auto& eval = locus::tools::group(app, "eval", "Measure the matchers on real data sets");
    auto* cmd = eval.add_subcommand("relative", "Relative positioning (Bonjorn López 2016) in simulation: two walkers, relative-direction error per method");
    auto args = std::make_shared<Args>();
    auto& c = args->config;
    cmd->add_option("--runs", args->runs, "walks per method (seeds seed…seed+runs−1)")->capture_default_str()->check(CLI::Range(1, 100000));
    cmd->add_option("--seed", args->seed, "first seed")->capture_default_str();
    cmd->add_option("--start-distance", c.start_distance, "m between the two at the start")->capture_default_str()->check(CLI::Range(2.0, 250.0));
    cmd->add_option("--seconds", c.seconds, "walking time scored")->capture_default_str()->check(CLI::Range(1.0, 3600.0));
    cmd->add_option("--shadowing", c.shadowing_db, "RSSI noise σ (dB)")->capture_default_str()->check(CLI::Range(0.0, 20.0));
    cmd->add_option("--initial-spread", c.initial_spread_deg, "A's first heading within ± this of B (degrees)")->capture_default_str()->check(CLI::Range(0.0, 180.0));
    cmd->add_option("--rssi-window", c.rssi_window, "readings averaged by rssi-mean")->capture_default_str()->check(CLI::Range(1, 100));
    cmd->add_option("--min-rho", c.estimator.min_rho, "m walked from the reference before a weight is formed")
        ->capture_default_str()->check(CLI::Range(0.1, 50.0));
    cmd->add_option("--fix-sigma", c.fix_sigma, "both-fixes: per-axis error of each fused fix (m)")->capture_default_str()->check(CLI::Range(0.0, 50.0));
    cmd->add_option("--range-v-sigma", c.range_kalman.v_walk_sigma, "rssi-kalman: drift of the range rate per metre walked")
        ->capture_default_str()->check(CLI::Range(0.0, 5.0));
    cmd->add_flag("!--no-follow", c.follow_estimate, "A keeps its first heading instead of following the estimate");
    cmd->add_flag("--json", args->json, "print the figures as JSON");
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_eval_relative
