// `locus replay`: a recorded or simulated walk through the real PDR, fixes from a running server,
// one fusion rule (or every method), and the track's error against the truth. The particle and
// Kalman filters map-match on the floor plan the server holds for the radio map's floor when there
// is one (--walls), else on the walk file's rooms and doors. A walk with anchors at known positions
// (locus sim --scenario open_area) also gets the Kalman-fusion paper's ranging methods
// (docs/spec.md §8 "Sources"), ranged in-process from the anchors the walk file lists
// (sim/ranging_eval.hpp).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "command_registry.hpp"
#include "datasets/ipin_log.hpp"
#include "ipin_replay.hpp"
#include "live_track.hpp"
#include "locus/api/client.hpp"
#include "locus/motion/fusion/walk_filter.hpp"
#include "locus/motion/fusion/walk_runner.hpp"
#include "sim/evaluate.hpp"
#include "sim/ranging_eval.hpp"
#include "sim/walk_io.hpp"

namespace locus_cli_replay {
namespace {

using namespace locus;
using nlohmann::json;

struct Args {
    std::string server = "http://127.0.0.1:8080";
    std::string api_key;
    std::int64_t radiomap = 0;
    // The best causal method on real phone walks (docs/fusion.md, "Real walks").
    std::string rule = "walk_pf";
    std::string algorithm = "wknn";
    int k = 3;
    std::string file;
    std::string format = "json";
    bool upload_survey = false;
    std::string walls = "auto";  // file | server | auto
    std::string live;            // a server to post the fused track to as a live track
    std::int64_t live_map = 0;
    double live_speed = 1.0;
    // A GetSensorData/IPIN logfile (tools/ipin_replay.hpp): the map it walks, and what the trackers take.
    std::int64_t map = 0;
    bool known_start = false, no_gnss = false, no_ble = false, no_offset = false, server_defaults = false;
    std::string fusion_options;  // a logfile's walk_pf: the track's fusion_options (a JSON object)
};

// What the filters map-match on, and where it came from (said on stderr and in the JSON).
struct Walls {
    std::optional<fusion::Walkable> map;
    std::string source;  // "server", "file" or "none"
    std::int64_t floor_id = 0;  // the radio map's floor (0 when not asked: --walls file)
};

Walls choose_walls(api::Client& client, const Args& a, const sim::Walk& walk) {
    const Walls from_file{walk.map, walk.map ? "file" : "none", 0};
    if (a.walls == "file") return from_file;
    const std::int64_t floor_id = client.radiomap(a.radiomap).floor_id;
    auto plan = client.plan(floor_id);
    const std::string floor = "floor " + std::to_string(floor_id) + " (radio map " + std::to_string(a.radiomap) + "'s)";
    if (plan && !plan->spaces.empty()) {
        std::cerr << "map matching on " << floor << " plan from the server: " << plan->spaces.size() << " spaces, "
                  << plan->walls.size() << " walls, " << plan->doors.size() << " doors\n";
        return {fusion::Walkable::from_plan(std::move(*plan)), "server", floor_id};
    }
    const std::string why = plan ? floor + " plan on the server has no spaces" : floor + " has no plan on the server";
    if (a.walls == "server")
        throw tools::CommandError(why + ": --walls file (or auto) map-matches on the walk file's rooms and doors");
    std::cerr << (walk.map ? "map matching on the walk file's rooms and doors: " : "no map matching (the walk file has no rooms either): ")
              << why << "\n";
    return {walk.map, walk.map ? "file" : "none", floor_id};
}

// Survey scans in the walk become RPs on the server, each file's scans once (upload ids).
void upload_survey(api::Client& client, const sim::Walk& walk, std::int64_t radiomap) {
    for (const auto& sp : walk.survey) {
        const auto rp = client.ensure_rp(radiomap, sp.name, sp.at.x, sp.at.y);
        api::ScanUpload up;
        up.upload_id = "walk-" + walk.scenario + "-" + std::to_string(walk.seed) + "-" + sp.name;
        up.scans = sp.scans;
        client.upload(rp.id, up);
    }
}

json track_json(const sim::NamedTrack& t, const sim::Walk& walk) {
    json points = json::array();
    for (const auto& p : t.track) {
        json o = {{"t", p.t_s}, {"x", p.at.x}, {"y", p.at.y}};
        if (const auto truth = walk.truth_at(p.t_s)) o["error_m"] = distance(p.at, *truth);
        points.push_back(o);
    }
    json out = {{"method", t.method}, {"points", points}};
    if (walk.has_truth()) {
        const auto s = sim::score(t, walk);
        out["mean_error_m"] = s.mean_error_m;
        out["final_error_m"] = s.final_error_m;
        out["p95_error_m"] = s.p95_error_m;
    }
    return out;
}

// fusion::WalkFilter over the walk: it knows no start and learns the compass's rotation from
// the fixes (here the PDR heading is already the floor's, so it learns about none); its track
// begins at the first fix.
sim::Track walk_pf_track(const std::vector<sim::PdrStep>& steps, const std::vector<sim::Fix>& fixes,
                         const std::optional<fusion::Walkable>& map, std::uint64_t seed) {
    fusion::WalkFilterConfig cfg;
    cfg.seed = seed;
    fusion::WalkFilter pf(map, cfg);
    sim::Track track;
    const std::vector<double> step_t = fusion::times_of(steps, &sim::PdrStep::t_s), fix_t = fusion::times_of(fixes, &sim::Fix::t_s);
    fusion::WalkHandlers handlers;
    handlers.step = [&](std::size_t i) {
        pf.step(steps[i].length_m, steps[i].heading_rad);
        if (pf.started()) track.push_back({steps[i].t_s, pf.position()});
    };
    handlers.fix = [&](std::size_t j) {
        pf.fix(fixes[j].at, fixes[j].cov);
        track.push_back({fixes[j].t_s, pf.position()});
    };
    fusion::run_walk({.step = step_t, .fix = fix_t}, handlers);  // a step before a fix of its instant
    return track;
}

void run(const Args& a) {
    if (a.format != "json" && a.format != "csv") throw tools::CommandError("--format must be json or csv");
    const auto algorithm = match::parse_algorithm(a.algorithm);
    if (!algorithm) throw tools::CommandError("unknown --algorithm '" + a.algorithm + "'");
    const bool all = a.rule == "all";
    const std::vector<std::string> methods = {"pdr", "wifi", "only_wifi", "midpoint", "midpoint_threshold",
                                              "proportional", "proportional2", "kalman", "particle", "walk_pf"};
    const std::vector<std::string> ranging_methods = {"trilateration", "multilateration", "kalman_trilateration", "kalman_ranging",
                                                      "ekf_ranging"};
    const bool ranging_rule = std::find(ranging_methods.begin(), ranging_methods.end(), a.rule) != ranging_methods.end();
    if (!all && !ranging_rule && std::find(methods.begin(), methods.end(), a.rule) == methods.end())
        throw tools::CommandError("unknown --rule '" + a.rule + "' (only_wifi, midpoint, midpoint_threshold, "
                                  "proportional, proportional2, kalman, particle, walk_pf, pdr, wifi, all; with "
                                  "anchors: trilateration, multilateration, kalman_trilateration, kalman_ranging, ekf_ranging)");

    const sim::Walk walk = sim::load_walk(a.file);
    if (ranging_rule && walk.anchors.empty())
        throw tools::CommandError("--rule " + a.rule + " needs a walk with anchors at known positions (" + a.file +
                                  " lists none; locus sim --scenario open_area writes such walks)");
    api::ClientOptions opts;
    opts.base_url = a.server;
    opts.api_key = a.api_key;
    api::Client client(opts);
    if (a.upload_survey) upload_survey(client, walk, a.radiomap);

    sim::EvalConfig cfg;
    cfg.algorithm = *algorithm;
    cfg.match_options.k = a.k;
    cfg.particle.seed = walk.seed;  // as `locus sim --evaluate`, so both runs are comparable
    const auto steps = sim::run_pdr(walk);
    std::vector<sim::Fix> fixes;
    int no_match = 0;
    for (const auto& scan : walk.scans) {
        if (scan.readings.empty()) continue;
        api::LocalizeRequest req;
        req.algorithm = a.algorithm;
        req.scans = {scan.readings};
        req.options = {{"k", a.k}};
        try {
            const auto r = client.localize_radiomap(a.radiomap, req);
            fixes.push_back(sim::make_fix(scan.t_s, static_cast<int>(scan.readings.size()), r, a.k,
                                          cfg.fix_sigma_floor_m));
        } catch (const api::ApiError& e) {
            if (e.code() != "no_match") throw;
            ++no_match;  // a scan that matches nothing gives no fix; PDR carries on
        }
    }
    if (fixes.empty() && no_match > 0)
        throw tools::CommandError("no scan of " + a.file + " matched any AP of radio map " + std::to_string(a.radiomap) +
                                  " (" + std::to_string(no_match) + " scans, every one answered no_match): is it the walk's "
                                  "radio map? --upload-survey puts the walk's survey scans into it first");
    const Walls walls = choose_walls(client, a, walk);
    auto tracks = sim::run_methods(steps, fixes, walk.start, walls.map, cfg);
    if (all || a.rule == "walk_pf") tracks.push_back({"walk_pf", walk_pf_track(steps, fixes, walls.map, walk.seed)});
    if (!walk.anchors.empty()) {
        const sim::RangingEvalConfig rc;
        for (auto& t : sim::run_ranging_methods(steps, sim::run_ranging(walk, rc), walk.start, rc,
                                                walls.map ? walls.map->floor_plan : nullptr))
            tracks.push_back(std::move(t));
    }

    json out = {{"file", a.file}, {"radiomap", a.radiomap}, {"algorithm", a.algorithm}, {"steps", steps.size()},
                {"fixes", fixes.size()}, {"no_match", no_match}, {"walls", walls.source}, {"tracks", json::array()}};
    if (walls.floor_id) out["floor_id"] = walls.floor_id;
    for (const auto& t : tracks) {
        if (!all && t.method != a.rule) continue;
        if (a.format == "csv") {
            std::cout << "method,t,x,y" << (walk.has_truth() ? ",error_m" : "") << "\n";
            for (const auto& p : t.track) {
                std::cout << t.method << "," << p.t_s << "," << p.at.x << "," << p.at.y;
                if (const auto truth = walk.truth_at(p.t_s)) std::cout << "," << distance(p.at, *truth);
                std::cout << "\n";
            }
        } else {
            out["tracks"].push_back(track_json(t, walk));
        }
    }
    if (!a.live.empty()) {
        const std::string method = all ? "particle" : a.rule;
        const auto t = std::find_if(tracks.begin(), tracks.end(), [&](const sim::NamedTrack& nt) { return nt.method == method; });
        if (t == tracks.end()) throw tools::CommandError("no " + method + " track to post live (the particle filter needs walls)");
        std::vector<tools::LivePoint> points;
        for (const auto& p : t->track) points.push_back({p.t_s, p.at});
        api::ClientOptions live_opts;
        live_opts.base_url = a.live;
        api::Client live(live_opts);
        tools::LiveOptions lo;
        lo.map_id = a.live_map;
        lo.floor_id = walls.floor_id ? walls.floor_id : client.radiomap(a.radiomap).floor_id;
        lo.label = walk.scenario + " seed " + std::to_string(walk.seed) + " (" + method + ")";
        lo.speed = a.live_speed;
        const auto key = tools::post_live(live, points, lo, std::cerr);
        out["live_track"] = {{"id", key.id}, {"token", key.token}, {"method", method}};
    }
    if (a.format == "json") std::cout << out.dump() << "\n";
    else if (walk.has_truth())
        for (const auto& t : tracks)
            if (all || t.method == a.rule) {
                const auto s = sim::score(t, walk);
                std::cerr << t.method << ": mean " << s.mean_error_m << " m, final " << s.final_error_m << " m\n";
            }
}

// A GetSensorData/IPIN logfile: the map's floors, one of the IPIN trackers or the server's
// thin-client path (tools/ipin_replay.hpp).
void run_log(const Args& a) {
    if (a.map <= 0) throw tools::CommandError("a logfile replays against a map: --map ID (every floor; not --radiomap)");
    if (a.radiomap > 0) throw tools::CommandError("--radiomap is for a walk file; a logfile takes --map");
    if (!a.live.empty() || a.upload_survey) throw tools::CommandError("--live and --upload-survey take walk files (a logfile's walk_pf posts to a live track itself)");
    if (a.format != "json") throw tools::CommandError("a logfile replays as json");
    const bool live = a.rule == "walk_pf" || a.rule == "thin";
    if (live && a.no_offset) throw tools::CommandError("--no-offset is for kalman and pdr: walk_pf's live track learns its phone's offset itself");
    if (!live && !a.fusion_options.empty()) throw tools::CommandError("--fusion-options opens walk_pf's live track; --rule " + a.rule + " opens none");
    api::ClientOptions opts;
    opts.base_url = a.server;
    opts.api_key = a.api_key;
    api::Client client(opts);
    tools::ipin::ReplayOptions o;
    o.file = a.file;
    o.map = a.map;
    o.rule = a.rule;
    o.known_start = a.known_start;
    o.gnss = !a.no_gnss;
    o.ble = !a.no_ble;
    o.offset = !a.no_offset;
    o.fusion_options = a.fusion_options;
    std::cout << tools::ipin::replay_log(client, o, std::cerr).dump() << "\n";
}

LOCUS_COMMAND("replay", [](CLI::App& app) {
    auto args = std::make_shared<Args>();
    auto* cmd = app.add_subcommand("replay", "Run a walk file through PDR, fixes from a server, and fusion");
    cmd->add_option("--server", args->server, "server base URL (default: $LOCUS_SERVER, else http://127.0.0.1:8080)")->envname("LOCUS_SERVER");
    cmd->add_option("--api-key", args->api_key, "API key (for --upload-survey)")->envname("LOCUS_API_KEY");
    cmd->add_option("--radiomap", args->radiomap, "radio map to localize against (a walk file)")->check(CLI::PositiveNumber);
    cmd->add_option("--map", args->map, "map to localize against, every floor (a GetSensorData/IPIN logfile)")->check(CLI::PositiveNumber);
    cmd->add_flag("--known-start", args->known_start, "a logfile's first POSI landmark given to the tracker");
    cmd->add_flag("--no-gnss", args->no_gnss, "a logfile's GNSS fixes left out");
    cmd->add_flag("--no-ble", args->no_ble, "a logfile's beacon readings left out");
    cmd->add_flag("--server-defaults", args->server_defaults, "a logfile's walk_pf (or thin): the live track opened with no fusion_options, as a phone opens it (the default)");
    cmd->add_option("--fusion-options", args->fusion_options,
                    "a logfile's walk_pf (or thin): the live track's fusion_options, a JSON object (docs/tracks.md), instead of the server's defaults")
        ->excludes(cmd->get_option("--server-defaults"));
    cmd->add_flag("--no-offset", args->no_offset, "a logfile's scans sent as read (kalman and pdr learn no phone offset; walk_pf's server learns its own)");
    cmd->add_option("--rule", args->rule, "fusion rule, kalman, particle, walk_pf (the default: best on real walks), pdr, wifi, "
                    "or all; for a logfile walk_pf (the server's live-track filter, as a phone gets it; thin is the same), kalman, pdr or wifi; for a walk with anchors also trilateration, multilateration, kalman_trilateration (alias: kalman_seed, "
                    "deprecated), kalman_ranging, ekf_ranging")->capture_default_str();
    cmd->add_option("--algorithm", args->algorithm, "matcher the server uses")->capture_default_str();
    cmd->add_option("--k", args->k, "k for knn/wknn/bayes")->capture_default_str()->check(CLI::Range(1, 100));
    cmd->add_option("--format", args->format, "json (tracks with errors) or csv")->capture_default_str();
    cmd->add_option("--walls", args->walls,
                    "what the particle and Kalman filters map-match on: the server's plan of the radio map's floor, "
                    "the walk file's rooms and doors, or auto (the server's plan when the floor has one)")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "server", "file"}));
    cmd->add_flag("--upload-survey", args->upload_survey,
                  "first create the walk's survey RPs on the radio map and upload their scans (idempotent)");
    auto* live = cmd->add_option("--live", args->live, "also post the fused track (--rule's; particle for all) to this server as a live track");
    cmd->add_option("--live-map", args->live_map, "map of the live track (the radio map's floor is its floor)")
        ->needs(live)->check(CLI::PositiveNumber);
    cmd->add_option("--live-speed", args->live_speed, "1: post in real time, 10: ten times faster, 0: all at once")
        ->capture_default_str()->check(CLI::Range(0.0, 1000.0));
    live->needs(cmd->get_option("--live-map"));
    cmd->add_option("FILE", args->file, "walk file (locus sim --out, or a recording) or a GetSensorData/IPIN logfile")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->callback([args] {
        if (args->rule == "kalman_seed") args->rule = "kalman_trilateration";  // the method's deprecated name
        if (datasets::ipin::file_looks_like_log(args->file)) {
            run_log(*args);
            return;
        }
        if (args->map > 0) throw tools::CommandError("--map is for a logfile; a walk file takes --radiomap");
        if (args->radiomap <= 0) throw tools::CommandError("--radiomap is required for a walk file");
        run(*args);
    });
});

}  // namespace

}  // namespace locus_cli_replay
