// `locus sim`: the seeded walking simulator (docs/spec.md §7.2). Writes a walk file (--out) and/or
// scores every positioning method on it (--evaluate); --runs averages consecutive seeds. The
// particle and Kalman filters map-match on the scenario's rooms and doors, on the same floor
// as a floor plan (--walls plan), or on the plan a server holds for a floor (--server --floor).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <initializer_list>
#include <utility>
#include <vector>

#include "command_registry.hpp"
#include "locus/api/client.hpp"
#include "locus/motion/fusion/rooms_plan.hpp"
#include "sim/evaluate.hpp"
#include "sim/generator.hpp"
#include "sim/ranging_eval.hpp"
#include "sim/scenario.hpp"
#include "sim/walk_io.hpp"
#include "walk_reality.hpp"

namespace locus_cli_sim {
namespace {

using namespace locus;

struct Args {
    std::string scenario;
    std::uint64_t seed = 1;
    int runs = 1;
    std::string out;
    bool evaluate = false;
    bool json = false;
    std::string algorithm = "wknn";
    int k = 3;
    double lambda = 4.0;
    int nmax = 10;
    int gamma = 2;
    int particles = 1000;
    double fix_sigma_floor = sim::EvalConfig{}.fix_sigma_floor_m;
    double kalman_latency = sim::EvalConfig{}.kalman_fix_latency_s;
    double particle_latency = sim::EvalConfig{}.particle_fix_latency_s;
    double scale_sigma = fusion::ParticleConfig{}.initial_scale_sigma;
    std::vector<std::string> particle_set;  // key=value overrides of fusion::ParticleConfig
    sim::SimConfig walk;  // defaults of the simulator; the options below override a few
    std::string walls = "rooms";  // rooms | plan; or the plan of --floor on --server
    bool walls_given = false;
    std::string server;
    std::string api_key;
    std::int64_t floor = 0;
    bool put_plan = false;
    std::string kalman_walls = "snap";  // block | snap
    std::string report;  // "ranging": the Kalman-fusion paper's table 1 side by side
    sim::RangingEvalConfig ranging;
};

// Table 1 of the Kalman-fusion paper (docs/spec.md §8 "Sources"): final-position
// error over its 20 walks, m: max, min, mean.
struct PaperRow {
    const char* method;
    const char* ours;
    double max, min, mean;
};
constexpr PaperRow kPaperTable1[] = {{"trilateration", "trilateration", 5.872, 1.258, 2.767},
                                {"PDR", "pdr", 4.216, 0.801, 2.384},
                                {"Kalman (proposed)", "kalman_trilateration", 3.18, 0.417, 1.224}};

// Final-position errors of each method over the walks, for the paper's max / min / mean.
void print_ranging_report(const std::map<std::string, std::vector<double>>& finals, const Args& a) {
    std::string notes;
    auto stats = [&](const std::string& m) {
        const auto& v = finals.at(m);
        if (static_cast<int>(v.size()) < a.runs)
            notes += "  " + m + ": " + std::to_string(a.runs - static_cast<int>(v.size())) + " of the walks had no fix at all\n";
        double lo = v.front(), hi = v.front(), sum = 0.0;
        for (double e : v) lo = std::min(lo, e), hi = std::max(hi, e), sum += e;
        return std::array<double, 3>{hi, lo, sum / static_cast<double>(v.size())};
    };
    std::printf("\nthe Kalman-fusion paper's comparison (its table 1): final-position error over %d walks (seeds %llu..%llu), m\n", a.runs,
                static_cast<unsigned long long>(a.seed), static_cast<unsigned long long>(a.seed + a.runs - 1));
    std::printf("%-22s %8s %8s %8s   %-18s %8s %8s %8s\n", "method (ours)", "max", "min", "mean", "the paper", "max",
                "min", "mean");
    for (const PaperRow& r : kPaperTable1) {
        const auto s = stats(r.ours);
        std::printf("%-22s %8.2f %8.2f %8.2f   %-18s %8.2f %8.2f %8.2f\n", r.ours, s[0], s[1], s[2], r.method, r.max,
                    r.min, r.mean);
    }
    for (const char* m : {"multilateration", "kalman_ranging", "ekf_ranging"}) {
        const auto s = stats(m);
        std::printf("%-22s %8.2f %8.2f %8.2f\n", m, s[0], s[1], s[2]);
    }
    const double target = 0.7 * kPaperTable1[2].mean;
    const double ours = stats("ekf_ranging")[2];
    std::printf("ours (ekf_ranging: multilateration inside the Kalman update) %.2f m against the target %.3f m "
                "(30 %% below the paper's %.3f m): %s\n",
                ours, target, kPaperTable1[2].mean, ours <= target ? "met" : "NOT met");
    std::printf("%s", notes.c_str());
}

// The floor the filters map-match on, and a word for where it came from.
struct Walls {
    fusion::Walkable map;
    std::string source;  // "rooms", "plan" (converted here) or "server"
};

Walls choose_walls(const Args& a, const sim::Scenario& sc) {
    if (a.server.empty() != (a.floor == 0)) throw tools::CommandError("--server and --floor go together");
    if (a.put_plan && a.floor == 0) throw tools::CommandError("--put-plan needs --server and --floor");
    if (a.walls_given && a.floor != 0)
        throw tools::CommandError("--walls and --floor both say what to map-match on: give one of them");
    if (a.floor == 0) {
        if (a.walls == "rooms") return {sc.map, "rooms"};
        return {fusion::Walkable::from_plan(fusion::rooms_plan(sc.map)), "plan"};
    }
    api::ClientOptions opts;
    opts.base_url = a.server;
    opts.api_key = a.api_key;
    api::Client client(opts);
    const std::string floor = "floor " + std::to_string(a.floor);
    if (a.put_plan) {
        // The scenario's room ids are its own: the server keeps the floor's rooms in step with
        // the plan by name (it adopts or makes the room of each space's name) and would refuse
        // a room_id that is not one of the floor's rooms.
        auto plan = fusion::rooms_plan(sc.map);
        for (auto& space : plan.spaces) space.room_id.reset();
        client.put_plan(a.floor, plan);
        std::cerr << "put scenario " << sc.name << "'s rooms and doors on " << floor << " as its plan\n";
    }
    auto plan = client.plan(a.floor);
    if (!plan || plan->spaces.empty())
        throw tools::CommandError(floor + (plan ? "'s plan has no spaces" : " has no plan") +
                                  " on the server (--put-plan puts the scenario's there first)");
    std::cerr << "map matching on " << floor << "'s plan from the server: " << plan->spaces.size() << " spaces, "
              << plan->walls.size() << " walls, " << plan->doors.size() << " doors\n";
    return {fusion::Walkable::from_plan(std::move(*plan)), "server"};
}

// For the particle filter's tuning sweeps (docs/fusion.md): any numeric ParticleConfig field.
void set_particle_field(fusion::ParticleConfig& c, const std::string& kv) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw tools::CommandError("--particle-set wants key=value, got '" + kv + "'");
    const std::string key = kv.substr(0, eq);
    double v = 0.0;
    try {
        v = std::stod(kv.substr(eq + 1));
    } catch (const std::exception&) {
        throw tools::CommandError("--particle-set " + key + ": not a number");
    }
    const std::map<std::string, double*> fields = {
        {"initial_sigma_m", &c.initial_sigma_m},
        {"initial_bias_sigma_rad", &c.initial_bias_sigma_rad},
        {"initial_scale_sigma", &c.initial_scale_sigma},
        {"heading_sigma_rad", &c.heading_sigma_rad},
        {"bias_walk_sigma_rad", &c.bias_walk_sigma_rad},
        {"length_sigma", &c.length_sigma},
        {"disturbed_heading_sigma_rad", &c.disturbed_heading_sigma_rad},
        {"retry_heading_sigma_rad", &c.retry_heading_sigma_rad},
        {"blocked_weight", &c.blocked_weight},
        {"outlier_floor", &c.outlier_floor},
        {"resample_fraction", &c.resample_fraction},
        {"roughening_m", &c.roughening_m},
        {"injection_likelihood", &c.injection_likelihood},
        {"injection_fraction", &c.injection_fraction},
    };
    if (key == "blocked_retries") {
        c.blocked_retries = static_cast<int>(v);
        return;
    }
    const auto it = fields.find(key);
    if (it == fields.end()) throw tools::CommandError("--particle-set: unknown key '" + key + "'");
    *it->second = v;
}

void run(const Args& a) {
    const sim::Scenario& sc = sim::scenario(a.scenario);
    if (a.runs < 1) throw tools::CommandError("--runs must be at least 1");
    if (!a.evaluate && a.out.empty()) throw tools::CommandError("nothing to do: give --out FILE and/or --evaluate");
    if (!a.out.empty() && a.runs != 1) throw tools::CommandError("--out writes one walk: use it with --runs 1");
    sim::EvalConfig cfg;
    const auto algorithm = match::parse_algorithm(a.algorithm);
    if (!algorithm) throw tools::CommandError("unknown --algorithm '" + a.algorithm + "'");
    cfg.algorithm = *algorithm;
    cfg.match_options.k = a.k;
    cfg.rules.lambda_m = a.lambda;
    cfg.rules.n_max = a.nmax;
    cfg.rules.gamma = a.gamma;
    cfg.particle.particles = a.particles;
    cfg.fix_sigma_floor_m = a.fix_sigma_floor;
    cfg.kalman_fix_latency_s = a.kalman_latency;
    cfg.particle_fix_latency_s = a.particle_latency;
    cfg.particle.initial_scale_sigma = a.scale_sigma;
    for (const std::string& kv : a.particle_set) set_particle_field(cfg.particle, kv);
    const Walls walls = choose_walls(a, sc);
    cfg.kalman.walls_block_steps = a.kalman_walls == "block";

    std::vector<std::string> order;
    std::map<std::string, sim::Score> sums;
    double distance_abs = 0.0, distance_sq = 0.0;  // PDR distance error, relative
    // The WiFi fixes' errors, for the same correlation `locus eval walks --reality` measures.
    std::vector<tools::walks::RealityStats> radio;
    std::map<std::string, std::vector<double>> finals;  // per method, one final error per walk
    for (int r = 0; r < a.runs; ++r) {
        const std::uint64_t seed = a.seed + static_cast<std::uint64_t>(r);
        sim::Walk walk = sim::simulate(sc, seed, a.walk);
        if (!a.out.empty()) sim::save_walk(a.out, walk);
        if (!a.evaluate) continue;
        walk.map = walls.map;
        cfg.particle.seed = seed;
        // Traini 2017 reports PDR distance against the walk (57.12 and 44.19 m for 52 m).
        double walked = 0.0;
        for (const sim::PdrStep& st : sim::run_pdr(walk)) walked += st.length_m;
        const double rel = walked / sc.path_length_m() - 1.0;
        distance_abs += std::abs(rel) / a.runs;
        distance_sq += rel * rel / a.runs;
        tools::walks::RealityStats& rs = radio.emplace_back();
        for (const sim::Fix& f : sim::run_matcher(walk, sim::build_index(walk), cfg))
            if (const auto truth = walk.truth_at(f.t_s)) {
                rs.fix_error.push_back({f.at.x - truth->x, f.at.y - truth->y});
                rs.fix_truth.push_back(*truth);
            }
        std::vector<sim::Score> scores = sim::evaluate(walk, cfg);
        if (!walk.anchors.empty())
            for (const sim::NamedTrack& t : sim::run_ranging_methods(sim::run_pdr(walk), sim::run_ranging(walk, a.ranging),
                                                                     walk.start, a.ranging, walls.map.floor_plan))
                scores.push_back(sim::score(t, walk));
        for (const sim::Score& s : scores) {
            if (s.points > 0) finals[s.method].push_back(s.final_error_m);  // a walk without a fix has no final
            if (!sums.count(s.method)) order.push_back(s.method);
            sim::Score& t = sums[s.method];
            t.method = s.method;
            t.mean_error_m += s.mean_error_m / a.runs;
            t.final_error_m += s.final_error_m / a.runs;
            t.p95_error_m += s.p95_error_m / a.runs;
            t.points += s.points;
        }
    }
    if (!a.evaluate) return;
    if (a.report == "ranging" && !finals.count("kalman_ranging"))
        throw tools::CommandError("--report ranging needs a scenario with anchors (open_area)");
    if (a.json) {
        nlohmann::ordered_json arr = nlohmann::ordered_json::array();
        for (const std::string& m : order) {
            const sim::Score& s = sums[m];
            nlohmann::ordered_json o = {{"scenario", sc.name},
                                {"walls", walls.source},
                                {"method", s.method},
                                {"mean_error_m", s.mean_error_m},
                                {"final_error_m", s.final_error_m},
                                {"p95_error_m", s.p95_error_m}};
            if (a.runs > 1) o["runs"] = a.runs, o["first_seed"] = a.seed;
            arr.push_back(o);
        }
        std::cout << arr.dump(2) << "\n";
        return;
    }
    std::printf("scenario %s (%.1f m2, walk %.1f m), seeds %llu..%llu, matcher %s, walls %s\n", sc.name.c_str(),
                sc.area_m2(), sc.path_length_m(), static_cast<unsigned long long>(a.seed),
                static_cast<unsigned long long>(a.seed + static_cast<std::uint64_t>(a.runs) - 1), a.algorithm.c_str(),
                walls.source.c_str());
    std::printf("%-20s %10s %10s %10s\n", "method", "mean_m", "final_m", "p95_m");
    for (const std::string& m : order) {
        const sim::Score& s = sums[m];
        std::printf("%-20s %10.2f %10.2f %10.2f\n", s.method.c_str(), s.mean_error_m, s.final_error_m, s.p95_error_m);
    }
    std::printf("pdr distance error: mean |e| %.1f %%, rms %.1f %%\n", 100.0 * distance_abs,
                100.0 * std::sqrt(distance_sq));
    std::printf("wifi error correlation between two fixes of a walk, by the distance between their truths:\n");
    for (const auto& b : tools::walks::error_correlation(radio, {0.0, 1.0, 2.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0}))
        std::printf("  %4.0f–%-4.0f m %6.2f  (%zu pairs)\n", b.lo, b.hi, b.correlation, b.pairs);
    if (a.report == "ranging") print_ranging_report(finals, a);
}

}  // namespace

LOCUS_COMMAND("sim", [](CLI::App& app) {
    auto args = std::make_shared<Args>();
    auto* cmd = app.add_subcommand("sim", "Simulate a walk on a test floor (IMU, WiFi, truth); write it or score it");
    cmd->add_option("--scenario", args->scenario, "ground, basement or open_area (anchors at known positions; seed004 is its deprecated alias)")->required();
    cmd->add_option("--seed", args->seed, "Walk seed (person, phone, noise)");
    cmd->add_option("--runs", args->runs, "Average over seeds seed..seed+runs-1");
    cmd->add_option("--out", args->out, "Write the walk as JSON lines (docs/fusion.md)");
    cmd->add_flag("--evaluate", args->evaluate, "Score pdr, wifi, the five rules, kalman and particle");
    cmd->add_flag("--json", args->json, "JSON array, one object per method");
    cmd->add_option("--algorithm", args->algorithm, "Matcher for the WiFi fixes (default wknn)");
    cmd->add_option("--k", args->k, "Matcher k (knn/wknn)");
    cmd->add_option("--lambda", args->lambda, "midpoint_threshold λ, m");
    cmd->add_option("--nmax", args->nmax, "proportional N_max");
    cmd->add_option("--gamma", args->gamma, "proportional γ");
    cmd->add_option("--particles", args->particles, "Particle count");
    cmd->add_option("--fix-sigma-floor", args->fix_sigma_floor, "Floor of a fix's σ per axis, m (kalman, particle)")
        ->capture_default_str();
    cmd->add_option("--kalman-latency", args->kalman_latency, "Age of a fix the Kalman filter compensates, s")
        ->capture_default_str();
    cmd->add_option("--particle-latency", args->particle_latency, "Age of a fix the particle filter compensates, s")
        ->capture_default_str();
    cmd->add_option("--scale-sigma", args->scale_sigma, "Particle filter's prior step-length scale spread")
        ->capture_default_str();
    cmd->add_option("--particle-set", args->particle_set,
                    "Override a particle filter setting, key=value (ParticleConfig field), repeatable");
    // Simulator knobs, for the calibration sweeps of docs/fusion.md.
    cmd->add_option("--scan-duration", args->walk.scan_duration_s, "Channel sweep of a scan, s")->capture_default_str();
    cmd->add_option("--heading-walk", args->walk.heading_walk_rad_per_sqrt_m,
                    "Compass rotation's random walk, rad/√m walked (0: a fixed compass offset alone)")->capture_default_str();
    cmd->add_option("--drift-db", args->walk.survey_drift_sigma_db, "Survey-to-walk RSS change, dB")->capture_default_str();
    cmd->add_option("--device-offset-db", args->walk.device_offset_sigma_db, "Phone vs survey phone RSS offset σ, dB")
        ->capture_default_str();
    cmd->add_option("--bounce-sigma", args->walk.bounce_log_sigma, "Person's step bounce spread (log σ)")
        ->capture_default_str();
    cmd->add_option("--length-sigma", args->walk.step_length_person_sigma, "Spread of the person's mean step length")
        ->capture_default_str();
    cmd->add_option("--misalignment", args->walk.misalignment_sigma_rad, "Phone yaw vs walking direction σ, rad")
        ->capture_default_str();
    // Map matching: which floor the particle and Kalman filters are constrained by.
    auto* walls = cmd->add_option("--walls", args->walls,
                    "rooms (the scenario's rooms and doors) or plan (the same floor as a floor plan, as a server "
                    "would hold it; the Kalman filter is map-matched too)")
        ->capture_default_str()
        ->check(CLI::IsMember({"rooms", "plan"}));
    cmd->add_option("--server", args->server, "with --floor: map-match on that floor's plan on this server");
    cmd->add_option("--floor", args->floor, "floor whose plan on --server the filters map-match on")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--api-key", args->api_key, "API key (for --put-plan)")->envname("LOCUS_API_KEY");
    cmd->add_option("--kalman-walls", args->kalman_walls,
                    "on a floor plan, the Kalman filter's steps are blocked by walls (block) or only snapped "
                    "into walkable space where they end (snap)")
        ->capture_default_str()
        ->check(CLI::IsMember({"block", "snap"}));
    // Scenarios with anchors (open_area): the ranging methods and their filters.
    cmd->add_option("--report", args->report, "ranging: the Kalman-fusion paper's table 1 (final errors) side by side with ours")
        ->check(CLI::IsMember({"ranging"}));
    cmd->add_option("--beacon-noise-db", args->walk.beacon_noise_sigma_db, "σ of one anchor reading, dB")
        ->capture_default_str();
    cmd->add_option("--beacon-offset-db", args->walk.beacon_phone_offset_sigma_db,
                    "σ of the phone's RSS offset against the anchors' configured power, dB")->capture_default_str();
    cmd->add_option("--ranging-window", args->ranging.window_s, "Anchor readings averaged per fix, s (the Kalman-fusion paper: 5)")
        ->capture_default_str()
        ->check(CLI::Range(0.1, 3600.0));
    cmd->add_option("--multilateration-window", args->ranging.multilateration_window_s,
                    "Anchor readings averaged per multilateration fix, s")->capture_default_str()
        ->check(CLI::Range(0.1, 3600.0));
    // --seed-r-sigma and --seed-q-sigma: the deprecated names of the next two.
    cmd->add_option("--trilateration-r-sigma,--seed-r-sigma", args->ranging.trilateration_kalman.fixed_r_sigma_m,
                    "Kalman on trilateration fixes (kalman_trilateration): R's σ per axis, m")
        ->capture_default_str();
    cmd->add_option("--trilateration-q-sigma,--seed-q-sigma", args->ranging.trilateration_kalman.kalman.step_sigma_floor_m,
                    "Kalman on trilateration fixes (kalman_trilateration): Q's σ per step, m")->capture_default_str();
    cmd->add_option("--ranging-q-per-m", args->ranging.kalman.kalman.step_sigma_per_m,
                    "Our ranging Kalman: Q's σ per metre walked")->capture_default_str();
    cmd->add_option("--ranging-r-floor", args->ranging.kalman.r_floor_m, "Our ranging Kalman: R's floor σ, m")
        ->capture_default_str();
    cmd->add_option("--ranging-r-scale", args->ranging.kalman.r_scale, "Our ranging Kalman: R = scale × the fix's covariance")
        ->capture_default_str();
    cmd->add_option("--ranging-latency", args->ranging.kalman_fix_latency_s,
                    "Our ranging Kalman: age of a window's fix, s")->capture_default_str();
    cmd->add_option("--ranging-gate", args->ranging.kalman.kalman.gate_chi2,
                    "Our ranging Kalman: reject a fix whose Mahalanobis distance² exceeds this (0: none)")
        ->capture_default_str();
    cmd->add_option("--ranging-learn-offset", args->ranging.learn_offset,
                    "Our ranging: learn the phone's RSS offset from earlier windows' residuals (true/false)")
        ->capture_default_str();
    cmd->add_option("--ranging-sigma-db", args->ranging.multilateration.sigma_db, "Multilateration's shadowing σ, dB")
        ->capture_default_str();
    cmd->add_option("--ekf-reading-sigma", args->ranging.ekf.reading_sigma_db,
                    "Tightly coupled filter: σ of one anchor reading about the model, dB")->check(CLI::PositiveNumber)->capture_default_str();
    cmd->add_option("--ekf-q-per-m", args->ranging.ekf.step_sigma_per_m,
                    "Tightly coupled filter: position noise σ per metre walked")->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd->add_option("--ekf-q-floor", args->ranging.ekf.step_sigma_floor_m,
                    "Tightly coupled filter: position noise σ per step, m")->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd->add_option("--ekf-offset-sigma", args->ranging.ekf.offset_sigma_db,
                    "Tightly coupled filter: prior σ of the phone's RSS offset, dB (0: not estimated)")->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd->add_option("--ekf-offset-walk", args->ranging.ekf.offset_walk_db_per_sqrt_s,
                    "Tightly coupled filter: the offset's random walk, dB/√s")->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd->add_option("--ekf-heading-bias", args->ranging.ekf.estimate_heading_bias,
                    "Tightly coupled filter: estimate the PDR heading's bias (true/false)")->capture_default_str();
    cmd->add_option("--ekf-heading-sigma", args->ranging.ekf.heading_bias_sigma_rad,
                    "Tightly coupled filter: prior σ of the heading bias, rad")->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd->add_option("--ekf-heading-walk", args->ranging.ekf.heading_walk_rad_per_sqrt_m,
                    "Tightly coupled filter: the heading bias's random walk, rad/√m")->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd->add_option("--ekf-step-lead", args->ranging.ekf.step_lead_s,
                    "Tightly coupled filter: a reading is taken where the phone was before the steps stamped in its "
                    "last this-many seconds")->check(CLI::NonNegativeNumber)->capture_default_str();
    cmd->add_option("--ekf-huber", args->ranging.ekf.huber_k,
                    "Tightly coupled filter: Huber threshold, in σ")->check(CLI::PositiveNumber)->capture_default_str();
    cmd->add_option("--ekf-iterations", args->ranging.ekf.iterations,
                    "Tightly coupled filter: Gauss–Newton iterations per update")->check(CLI::Range(1, 20))->capture_default_str();
    cmd->add_flag("--put-plan", args->put_plan, "first put the scenario's rooms and doors on --floor as its plan");
    cmd->callback([args, walls, cmd] {
        args->walls_given = walls->count() > 0;
        // A scenario's own simulator settings, where the command line did not set them.
        const sim::SimConfig base = sim::default_config(args->scenario);
        for (const auto& [option, field] : std::initializer_list<std::pair<const char*, double sim::SimConfig::*>>{
                 {"--heading-walk", &sim::SimConfig::heading_walk_rad_per_sqrt_m},
                 {"--misalignment", &sim::SimConfig::misalignment_sigma_rad},
                 {"--length-sigma", &sim::SimConfig::step_length_person_sigma},
                 {"--beacon-noise-db", &sim::SimConfig::beacon_noise_sigma_db}})
            if (cmd->get_option(option)->count() == 0) args->walk.*field = base.*field;
        run(*args);
    });
});

}  // namespace locus_cli_sim
