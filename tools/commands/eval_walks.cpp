// `locus eval walks DIR --server URL --radiomap ID`: real phone walks (the PUTMC walks under
// DIR/trajs, or one walk directory) through the real PDR, each scan localized by the server,
// and every positioning method; error at each scan's ground-truth point, per walk and pooled.
// walk_pf, the default, is the server's own live track of each walk (tools/putmc_live.hpp);
// walk_pf_local the same filter run here on this command's answers, for --set tuning.
// Causal (tools/walk_eval.hpp); --smooth adds an offline smoother, labelled as such. The floor
// is the radio map's: its height flips PUTMC's y (as `locus import putmc` did) and its plan,
// when it has one, is what the particle filters map-match on.
#include <chrono>
#include <cmath>
#include <atomic>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "locus/api/client.hpp"
#include "survey_connect.hpp"
#include "putmc_live.hpp"
#include "walk_eval.hpp"
#include "walk_reality.hpp"

namespace locus_cli_eval_walks {
namespace {

using namespace locus;
using namespace locus::tools;
namespace putmc = locus::datasets::putmc;
using nlohmann::json;

struct Args {
    ServerArgs server;
    std::string dir;
    std::int64_t radiomap = 0;
    std::string method = "all";
    std::string only;  // comma-separated walk names
    std::string algorithm = "wknn";
    int k = 4;
    bool json_out = false;
    bool smooth = false;
    bool walls = true;
    bool reality = false;  // the statistics the simulator is calibrated to, instead of the methods
    bool subarea = true;   // walk_pf's live tracks match their scans in the subarea (the server's default)
    int particles = 2000;
    int jobs = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::string> tune;  // --set KEY=VALUE
};

// Not a method: the live walk_pf track's scan fixes (each scan as its /steps matched it, in the
// track's subarea), scored like one.
constexpr const char* kScanFixes = "walk_pf.scan_fixes";

// --set KEY=VALUE: a method's parameter, for tuning (on walks 1–5 only: docs/fusion.md).
// walk_pf_local's by name, the other methods' as particle.NAME, kalman.NAME, rules.NAME (the
// live walk_pf runs the server's settings: a track's fusion_options are the way to others).
void apply_tuning(walks::Config& cfg, const std::vector<std::string>& kv) {
    auto& c = cfg.walk_filter;
    auto& pc = cfg.methods.particle;
    auto& rp = cfg.tuned_rules;
    double seed = static_cast<double>(c.seed), particles = pc.particles, n_max = rp.n_max, gamma = rp.gamma,
           backward = cfg.backward_particles, min_particles = c.min_particles;
    const std::map<std::string, double*> keys = {
        {"initial_sigma_m", &c.initial_sigma_m}, {"scale_mean", &c.scale_mean}, {"scale_sigma", &c.scale_sigma},
        {"heading_sigma_rad", &c.heading_sigma_rad}, {"offset_walk_rad", &c.offset_walk_rad}, {"scale_walk", &c.scale_walk},
        {"length_sigma", &c.length_sigma}, {"snap_rad", &c.snap_rad}, {"blocked_weight", &c.blocked_weight},
        {"fix_sigma_m", &c.fix_sigma_m}, {"outlier_floor", &c.outlier_floor}, {"reseed_fraction", &c.reseed_fraction},
        {"reseed_max_fraction", &c.reseed_max_fraction}, {"estimate_radius_m", &c.estimate_radius_m},
        {"resample_fraction", &c.resample_fraction}, {"seed", &seed}, {"hint_share", &c.hint_share},
        {"hint_sigma_rad", &c.hint_sigma_rad}, {"min_particles", &min_particles}, {"kld_epsilon", &c.kld_epsilon},
        {"kld_bin_m", &c.kld_bin_m}, {"kld_bin_rad", &c.kld_bin_rad}, {"cloud_share", &c.cloud_share},
        {"cloud_sigma_rad", &c.cloud_sigma_rad}, {"particle.particles", &particles},
        {"particle.initial_sigma_m", &pc.initial_sigma_m}, {"particle.initial_bias_sigma_rad", &pc.initial_bias_sigma_rad},
        {"particle.initial_scale_sigma", &pc.initial_scale_sigma}, {"particle.heading_sigma_rad", &pc.heading_sigma_rad},
        {"particle.bias_walk_sigma_rad", &pc.bias_walk_sigma_rad}, {"particle.length_sigma", &pc.length_sigma},
        {"particle.blocked_weight", &pc.blocked_weight}, {"particle.outlier_floor", &pc.outlier_floor},
        {"particle.injection_likelihood", &pc.injection_likelihood}, {"particle.injection_fraction", &pc.injection_fraction},
        {"particle.latency_s", &cfg.methods.particle_fix_latency_s}, {"fix_sigma_floor_m", &cfg.methods.fix_sigma_floor_m},
        {"kalman.step_sigma_per_m", &cfg.methods.kalman.step_sigma_per_m}, {"rules.lambda_m", &rp.lambda_m},
        {"rules.midpoint_wifi_weight", &rp.midpoint_wifi_weight}, {"rules.proportional2_min_r", &rp.proportional2_min_r},
        {"rules.n_max", &n_max}, {"rules.gamma", &gamma},
        {"smoother.backward_particles", &backward}};
    for (const auto& item : kv) {
        const auto eq = item.find('=');
        const auto it = keys.find(item.substr(0, eq));
        if (eq == std::string::npos || it == keys.end()) throw CommandError("--set: unknown parameter '" + item + "'");
        try {
            *it->second = std::stod(item.substr(eq + 1));
        } catch (const std::exception&) {
            throw CommandError("--set: '" + item + "' is not KEY=NUMBER");
        }
    }
    c.seed = static_cast<std::uint64_t>(seed);
    pc.particles = static_cast<int>(particles);
    c.min_particles = static_cast<int>(min_particles);
    rp.n_max = static_cast<int>(n_max);
    rp.gamma = static_cast<int>(gamma);
    cfg.backward_particles = static_cast<int>(backward);
}

json stats_json(const walks::Stats& s) {
    return {{"n", s.n}, {"mean_m", s.mean}, {"median_m", s.median}, {"p75_m", s.p75}, {"p95_m", s.p95}};
}

// One line per walk and the pooled figures the simulator's defaults are set from.
void print_reality(const std::vector<std::string>& dirs, const std::vector<walks::RealityStats>& rs) {
    constexpr double kDeg = 180.0 / 3.14159265358979323846;
    double ss4 = 0.0, metres4 = 0.0, ss = 0.0, metres = 0.0, steps_m = 0.0, truth_m = 0.0, err_sq = 0.0, err_sum = 0.0, range_sum = 0.0;
    std::size_t n_err = 0;
    std::printf("%-14s %9s %10s %14s %9s %9s\n", "walk", "intervals", "φ range °", "φ walk °/√m", "steps/m", "wifi m");
    for (std::size_t w = 0; w < rs.size(); ++w) {
        const auto& r = rs[w];
        double e = 0.0;
        for (const auto& v : r.fix_error) e += std::hypot(v.x, v.y), err_sq += v.x * v.x + v.y * v.y;
        err_sum += e;
        n_err += r.fix_error.size();
        ss4 += r.rotation_walk4_sum_sq, metres4 += r.rotation_walk4_metres;
        ss += r.rotation_walk_sum_sq, metres += r.rotation_walk_metres, steps_m += r.step_metres, truth_m += r.truth_metres;
        range_sum += r.rotation_range_rad;
        const double walk_sigma = r.rotation_walk_metres > 0.0 ? std::sqrt(r.rotation_walk_sum_sq / r.rotation_walk_metres) : 0.0;
        std::printf("%-14s %9zu %10.0f %14.1f %9.2f %9.2f%s\n", std::filesystem::path(dirs[w]).filename().string().c_str(),
                    r.intervals, r.rotation_range_rad * kDeg, walk_sigma * kDeg, r.truth_metres > 0.0 ? r.step_metres / r.truth_metres : 0.0,
                    r.fix_error.empty() ? 0.0 : e / static_cast<double>(r.fix_error.size()), r.mirrored ? "  (mirrored)" : "");
    }
    if (rs.empty()) return;
    std::printf("pooled: φ range %.0f° mean per walk; φ random walk %.1f°/√m (%.3f rad/√m), over 4 intervals %.1f°/√m (%.3f rad/√m); steps cover %.2f of the truth's "
                "scan-to-scan polyline; wifi error %.2f m mean, %.2f m rms per axis\n",
                range_sum / static_cast<double>(rs.size()) * kDeg, std::sqrt(ss / metres) * kDeg, std::sqrt(ss / metres),
                std::sqrt(ss4 / metres4) * kDeg, std::sqrt(ss4 / metres4),
                truth_m > 0.0 ? steps_m / truth_m : 0.0, n_err ? err_sum / static_cast<double>(n_err) : 0.0,
                n_err ? std::sqrt(err_sq / (2.0 * static_cast<double>(n_err))) : 0.0);
    std::printf("wifi error correlation between two fixes of a walk, by the distance between their truths:\n");
    for (const auto& b : walks::error_correlation(rs, {0.0, 1.0, 2.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0}))
        std::printf("  %4.0f–%-4.0f m %6.2f  (%zu pairs)\n", b.lo, b.hi, b.correlation, b.pairs);
}

void run(const Args& a) {
    const auto t_start = std::chrono::steady_clock::now();
    std::vector<std::string> dirs;
    try {
        dirs = putmc::walk_dirs(a.dir);
    } catch (const std::exception& e) {
        throw CommandError(e.what());
    }
    if (!a.only.empty()) {
        std::set<std::string> keep;
        std::stringstream ss(a.only);
        for (std::string w; std::getline(ss, w, ',');) keep.insert(w);
        std::erase_if(dirs, [&](const std::string& d) { return !keep.count(std::filesystem::path(d).filename().string()); });
    }
    if (dirs.empty()) throw CommandError("no walk under '" + a.dir + "' (a directory with acc.map, or one with trajs/ holding them)");

    api::Client client(a.server.client_options());
    const auto rm = client.radiomap(a.radiomap);
    const auto floor = client.floor(rm.floor_id);
    std::optional<fusion::Walkable> map;
    if (a.walls)
        if (auto plan = client.plan(rm.floor_id); plan && !plan->spaces.empty()) map = fusion::Walkable::from_plan(std::move(*plan));
    std::cerr << "floor " << floor.id << " (" << floor.width << " × " << floor.height << " m), "
              << (map ? "map matching on its plan" : "no plan: no map matching") << "\n";

    walks::Config cfg;
    cfg.smooth = a.smooth;
    cfg.methods.match_options.k = a.k;
    cfg.walk_filter.particles = a.particles;
    apply_tuning(cfg, a.tune);
    const auto names = walks::method_names(map.has_value(), a.smooth);
    if (a.method != "all" && std::find(names.begin(), names.end(), a.method) == names.end()) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        throw CommandError("unknown --method '" + a.method + "' (" + list + " or all)");
    }

    std::vector<walks::RealityStats> reality;
    std::vector<putmc::Walk> walk_data;
    std::vector<std::vector<std::optional<sim::Fix>>> walk_fixes;
    int no_match_total = 0;
    double http_s = 0.0;
    for (const auto& d : dirs) {
        putmc::Walk walk;
        try {
            walk = putmc::read_walk(d);
        } catch (const std::exception& e) {
            throw CommandError(e.what());
        }
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::optional<sim::Fix>> fixes;
        for (const auto& s : walk.scans) {
            if (s.readings.empty()) {
                fixes.push_back(std::nullopt);
                continue;
            }
            api::LocalizeRequest req;
            req.algorithm = a.algorithm;
            req.scans = {s.readings};
            req.options = {{"k", a.k}};
            try {
                const auto r = client.localize_radiomap(a.radiomap, req);
                fixes.push_back(sim::make_fix(s.t_s, static_cast<int>(s.readings.size()), r, a.k, cfg.methods.fix_sigma_floor_m));
            } catch (const api::ApiError& e) {
                if (e.code() != "no_match") throw;
                fixes.push_back(std::nullopt);
                ++no_match_total;
            }
        }
        http_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (a.reality) {
            reality.push_back(walks::reality_of(walk, fixes, floor.height));
            continue;
        }
        walk_data.push_back(std::move(walk));
        walk_fixes.push_back(std::move(fixes));
    }
    const auto t_filters = std::chrono::steady_clock::now();

    // The walks are independent and each filter has its own seed, so they run on several
    // threads with results identical to one thread's (the shared plan is only read).
    std::vector<walks::WalkResult> results(walk_data.size());
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto worker = [&] {
        for (std::size_t w; (w = next++) < walk_data.size();) {
            try {
                results[w] = walks::evaluate_walk(walk_data[w], walk_fixes[w], floor.height, map, cfg);
            } catch (...) {
                const std::lock_guard lock(failure_mutex);
                if (!failure) failure = std::current_exception();
            }
        }
    };
    {
        std::vector<std::jthread> pool;
        const int jobs = std::max(1, std::min<int>(a.jobs, static_cast<int>(walk_data.size())));
        for (int j = 1; j < jobs; ++j) pool.emplace_back(worker);
        worker();
    }
    if (failure) std::rethrow_exception(failure);
    const double filter_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_filters).count();
    // walk_pf is what a phone gets: each walk posted to a live track on the radio map's map, the
    // server's own filter answering (tools/putmc_live.hpp), one walk at a time (the API client
    // is one connection), so that the tracks' ids, the filters' seeds, follow the walks' order.
    const auto t_live = std::chrono::steady_clock::now();
    if (!a.reality && (a.method == "all" || a.method == "walk_pf")) {
        const std::int64_t map_id = client.get("/v1/buildings/" + std::to_string(floor.building_id)).at("map_id").get<std::int64_t>();
        for (std::size_t w = 0; w < walk_data.size(); ++w) {
            walks::LiveWalk live = walks::live_walk(client, map_id, walk_data[w], a.subarea);
            auto& tracks = results[w].tracks;
            std::erase_if(tracks, [](const walks::MethodTrack& t) { return t.method == "walk_pf" || t.method == kScanFixes; });
            tracks.push_back({"walk_pf", std::move(live.at_scan)});
            tracks.push_back({kScanFixes, std::move(live.scan_fix)});
            results[w].live_track = {live.track_id, live.token};
        }
    }
    const double live_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_live).count();
    for (const auto& r : results)
        if (r.fixes == 0)
            std::cerr << "locus: " << r.name << ": no scan localized (every one answered no_match): skipped in the figures\n";

    if (a.reality) {
        print_reality(dirs, reality);
        return;
    }
    if (map) {
        // A plan that does not line up with the walks (wrong scale, flip or offset) would make
        // map matching hurt: say how many ground-truth points it holds as walkable.
        std::size_t inside = 0, total = 0;
        for (const auto& r : results)
            for (const auto& p : r.truth) inside += map->inside(p), ++total;
        std::cerr << inside << " of " << total << " ground-truth points are walkable on the plan\n";
    }
    std::vector<std::string> shown = a.method == "all" ? names : std::vector<std::string>{a.method};
    if (a.method == "all" || a.method == "walk_pf") shown.insert(std::find(shown.begin(), shown.end(), "walk_pf") + 1, kScanFixes);
    json out = {{"radiomap", a.radiomap}, {"algorithm", a.algorithm}, {"k", a.k}, {"walls", map.has_value()},
                {"causal", "every method but the *_smoother ones: estimate at a scan from data up to that scan"},
                {"no_match", no_match_total}, {"walks", json::array()}, {"pooled", json::object()}};
    std::map<std::string, std::vector<double>> pooled;
    for (const auto& r : results) {
        json truth = json::array();
        for (const auto& p : r.truth) truth.push_back({p.x, p.y});
        json w = {{"walk", r.name}, {"truth", truth}, {"scans", r.truth.size()}, {"fixes", r.fixes}, {"steps", r.steps},
                  {"offset_deg", r.offset_deg}, {"mirrored", r.mirrored}, {"methods", json::object()}};
        if (r.live_track) w["live_track"] = {{"id", r.live_track->first}, {"token", r.live_track->second}};
        for (const auto& m : shown) {
            const auto e = walks::errors_of(r, m);
            w["methods"][m] = stats_json(walks::stats_of(e));
            if (a.json_out)
                for (const auto& t : r.tracks)
                    if (t.method == m) {
                        json pts = json::array();
                        for (const auto& p : t.at_scan) pts.push_back(p ? json::array({p->x, p->y}) : json());
                        w["methods"][m]["at_scans"] = pts;
                    }
            pooled[m].insert(pooled[m].end(), e.begin(), e.end());
        }
        out["walks"].push_back(w);
    }
    for (const auto& m : shown) out["pooled"][m] = stats_json(walks::stats_of(pooled[m]));
    const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    out["seconds"] = {{"total", total_s}, {"localize_http", http_s}, {"pdr_and_filters", filter_s}, {"live_tracks", live_s}};

    if (a.json_out) {
        std::cout << out.dump() << "\n";
        return;
    }
    char line[256];
    std::snprintf(line, sizeof line, "%-26s %6s %8s %8s %8s %8s\n", "method", "scans", "mean", "median", "p75", "p95");
    for (const auto& w : out["walks"]) {
        std::cout << w["walk"].get<std::string>() << " (" << w["scans"] << " scans, " << w["steps"] << " steps, offset "
                  << static_cast<int>(std::lround(w["offset_deg"].get<double>())) << "°" << (w["mirrored"].get<bool>() ? ", mirrored" : "")
                  << ")\n"
                  << line;
        for (const auto& m : shown) {
            const auto& s = w["methods"][m];
            char row[256];
            std::snprintf(row, sizeof row, "%-26s %6d %8.2f %8.2f %8.2f %8.2f\n", m.c_str(), s["n"].get<int>(),
                          s["mean_m"].get<double>(), s["median_m"].get<double>(), s["p75_m"].get<double>(), s["p95_m"].get<double>());
            std::cout << row;
        }
    }
    std::cout << "pooled (" << results.size() << " walks)\n" << line;
    for (const auto& m : shown) {
        const auto& s = out["pooled"][m];
        char row[256];
        std::snprintf(row, sizeof row, "%-26s %6d %8.2f %8.2f %8.2f %8.2f%s\n", m.c_str(), s["n"].get<int>(), s["mean_m"].get<double>(),
                      s["median_m"].get<double>(), s["p75_m"].get<double>(), s["p95_m"].get<double>(),
                      m.ends_with("_smoother") ? "  (offline: uses future data)" : "");
        std::cout << row;
    }
    std::snprintf(line, sizeof line, "%.2f s (localize over HTTP %.2f s, PDR and filters %.2f s, live tracks %.2f s)\n", total_s, http_s,
                  filter_s, live_s);
    std::cerr << line;
}

}  // namespace

LOCUS_COMMAND("eval-walks", [](CLI::App& app) {
    auto& eval = locus::tools::group(app, "eval", "Measure the matchers on real data sets");
    auto* cmd = eval.add_subcommand("walks", "Real phone walks (PUTMC format): every positioning method, error at the scans");
    auto args = std::make_shared<Args>();
    args->server.add_to(*cmd);
    cmd->add_option("--radiomap", args->radiomap, "radio map to localize against (locus import putmc prints it)")
        ->required()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--method", args->method, "one method, or all")->capture_default_str();
    cmd->add_option("--walks", args->only, "only these walks (comma-separated directory names)");
    cmd->add_option("--algorithm", args->algorithm, "matcher the server uses")->capture_default_str();
    cmd->add_option("--k", args->k, "k for knn/wknn")->capture_default_str()->check(CLI::Range(1, 100));
    cmd->add_option("--particles", args->particles, "walk_pf_local particles")->capture_default_str()->check(CLI::Range(10, 100000));
    cmd->add_option("--jobs", args->jobs, "walks evaluated at once (threads); the figures do not depend on it")
        ->capture_default_str()
        ->check(CLI::Range(1, 256));
    cmd->add_option("--set", args->tune, "a method's parameter KEY=VALUE, for tuning (walk_pf_local's by name; particle.*, kalman.*; rules.* sets the *_tuned rules)");
    cmd->add_flag("--json", args->json_out, "one JSON document instead of tables");
    cmd->add_flag("--reality", args->reality, "instead of the methods: the walks' compass drift, step coverage and WiFi error correlation (what the simulator is calibrated to)");
    cmd->add_flag("--smooth", args->smooth, "also the offline smoothers, RTS and forward-backward walk_pf_local (use each walk's future: not causal)");
    cmd->add_flag_callback("--no-subarea", [args] { args->subarea = false; },
                           "walk_pf's live tracks opened with fusion_options.subarea false: their scans matched on the whole map");
    cmd->add_flag_callback("--no-walls", [args] { args->walls = false; }, "ignore the floor's plan (no map matching)");
    cmd->add_option("DIR", args->dir, "PUTMC directory (with trajs/) or one walk directory")->required()->check(CLI::ExistingDirectory);
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_eval_walks
