// `locus eval ipin DIR --trials GLOB [--method yardstick|wifi|wifi-baro|pdr|walk_pf|all] [--train GLOB]
// [--server URL --map ID] [--known-start] [--no-gnss] [--no-ble] [--no-offset] [--json]`: positioning of the IPIN 2023 walks scored as
// the competition scores them (tools/ipin_eval.hpp, docs/ipin-import.md). Each held-out walk's WiFi
// scans are localized one by one (an estimate stamped at the scan's AppTimestamp); at each POSI
// instant the latest estimate at most 0.01 s after it counts; error = horizontal metres + 15 m
// per floor of difference; p75 as MATLAB's quantile. Also reported ("scans"): each scan's
// answer against its interpolated position (locus/survey/walk.hpp).
//
// Methods: `yardstick`, kNN k = 3 over the raw scans of the --train walks (one RP per scan,
// placed by the walking survey), powed representation (β = e), Sørensen distance, floor by
// vote (Torres-Sospedra et al. 2015, as in tools/fingerprint_eval.hpp); `wifi`, the server's
// answer to POST /v1/maps/{id}/localize with the scan and nothing else; `wifi-baro`, the same
// answers with their floor replaced by the barometric floor (locus/motion/fusion/baro_floor.hpp: the
// walk's pressure, the map's floor elevations, each answer's floor as a radio vote), estimates
// at each scan and every 0.5 s between (the last answer's position, the floor then); `walk_pf`
// (the default), what a phone gets: the walk posted to a live track on the map as a thin client
// posts it (tools/ipin_replay.hpp: steps, pressure, GNSS unless --no-gnss, BLE unless --no-ble,
// the scans), the server's own filter (docs/tracks.md) answering, the track opened with no
// options; `pdr` and `kalman`, baselines: the walk's IMU fused here with the server's answers,
// the barometer, GNSS and the map's BLE beacons, estimates every 0.5 s from the file's start
// (tools/ipin_track.hpp). Causal: an estimate at t uses only the samples and answers at or
// before t. --known-start gives the trackers (and wifi-baro's barometer) the first POSI
// landmark, as the competition gave its scoring walks' start. The
// server's answers are brought from their floor's frame into the venue's through the floors'
// georeferences (the same frame for every floor `locus import ipin` makes).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/ipin_log.hpp"
#include "floor_geo_json.hpp"
#include "ipin_eval.hpp"
#include "ipin_replay.hpp"
#include "ipin_track.hpp"
#include "ipin_venue.hpp"
#include "ipin_walk.hpp"
#include "locus/motion/fusion/baro_floor.hpp"
#include "locus/motion/fusion/walk_runner.hpp"
#include "locus/match/device_offset.hpp"
#include "locus/match/localize.hpp"
#include "survey_connect.hpp"
#include "walk_survey.hpp"

namespace locus_cli_eval_ipin {
namespace {

using namespace locus;
using namespace locus::tools;
using nlohmann::json;

struct Args {
    ServerArgs server;
    std::string dir;
    std::vector<std::string> trials;
    std::vector<std::string> train;
    std::string method = "all";
    std::int64_t map = 0;
    bool known_start = false;
    bool no_gnss = false;
    bool no_offset = false;
    bool no_ble = false;
    bool subarea = true;  // walk_pf's live tracks match their scans in the subarea (the server's default)
    bool json_out = false;
};

using ipin::LoadedWalk;
using ipin::MapFloors;

// The yardstick's index over the training walks' placed scans, one RP per scan.
struct Yardstick {
    match::Index index;
    match::Options options;
};

Yardstick yardstick(const std::vector<LoadedWalk>& train) {
    std::vector<match::IndexedRp> rps;
    double min_rss = 0.0;
    for (const auto& lw : train) {
        const auto truth = ipin::scan_truth(lw.walk);
        for (std::size_t i = 0; i < truth.size(); ++i) {
            if (!truth[i]) continue;
            match::IndexedRp r;
            r.rp.id = static_cast<long long>(rps.size() + 1);
            r.rp.name = lw.label + " scan " + std::to_string(i);
            r.rp.at = truth[i]->at;
            r.rp.scans = 1;
            r.rp.measurements = aggregate_scans({lw.walk.scans[i]});
            for (const auto& m : lw.walk.scans[i]) min_rss = std::min(min_rss, m.rss);
            r.floor_id = truth[i]->floor;
            r.building_id = 100;
            rps.push_back(std::move(r));
        }
    }
    if (rps.empty()) throw CommandError("the --train walks have no placed scan");
    match::IndexParams params;
    params.powed_beta = std::numbers::e;
    params.missing_rss = min_rss - 1.0;  // one below the weakest reading: every reading counts as heard
    Yardstick y{match::Index::build(rps, params), {}};
    y.options.k = 3;
    y.options.representation = match::Representation::powed;
    y.options.distance = match::Distance::sorensen;
    y.options.position_on_voted_floor = false;
    return y;
}


// wifi-baro: each server answer's floor replaced by the barometric floor. The events of the
// walk (pressure samples, scans, the 2 Hz ticks) are taken in time order, pressure first and a
// tick last at equal times (fusion::kStepsFirst), so every estimate uses only what came at or
// before it.
std::vector<std::optional<ipin::Fix>> with_baro_floor(const LoadedWalk& lw, const std::vector<std::optional<ipin::Fix>>& answers,
                                                      const std::vector<fusion::FloorLevel>& floors,
                                                      std::optional<int> start_floor, std::vector<ipin::Fix>& estimates) {
    constexpr double kTickS = 0.5;
    if (start_floor && std::none_of(floors.begin(), floors.end(), [&](const fusion::FloorLevel& f) { return f.floor == *start_floor; }))
        start_floor.reset();
    fusion::BaroFloor baro(floors, {}, start_floor);
    std::vector<std::optional<ipin::Fix>> per_scan(answers.size());
    std::optional<ipin::Fix> last;
    const auto& times = lw.walk.scan_times;
    const double end = std::max(times.empty() ? 0.0 : times.back(), lw.truth.empty() ? 0.0 : lw.truth.back().t);
    // From the first scan's half second to the last scan or POSI instant; none without scans.
    std::vector<double> ticks;
    if (!times.empty())
        for (double tick = std::floor(times.front() / kTickS) * kTickS; tick <= end; tick += kTickS) ticks.push_back(tick);
    const std::vector<double> pressure_t = fusion::times_of(lw.pressure, &datasets::ipin::PressureSample::t_s);
    fusion::WalkHandlers handlers;
    handlers.pressure = [&](std::size_t k) { baro.add_pressure(lw.pressure[k].t_s, lw.pressure[k].hpa); };
    handlers.fix = [&](std::size_t i) {
        if (!answers[i]) return;
        baro.add_radio_vote(answers[i]->floor);
        last = *answers[i];
        last->floor = baro.floor().value_or(answers[i]->floor);
        per_scan[i] = last;
        estimates.push_back(*last);
    };
    handlers.tick = [&](std::size_t k) {
        if (last) estimates.push_back({ticks[k], baro.floor().value_or(last->floor), last->at});
    };
    fusion::run_walk({.pressure = pressure_t, .fix = times, .tick = ticks}, handlers);
    return per_scan;
}


// Where each of the map's beacons is heard near (the check that it is stored where it stands):
// the readings at or above the trackers' BLE threshold, placed by the walking survey, their
// centroid and floor (the most frequent), against the stored position. A beacon stored at the
// wrong place shows as a large `off_m` (docs/ipin-import.md, "The beacons").
json beacon_check(const std::vector<LoadedWalk>& walks, const std::vector<ipin::Beacon>& beacons, const ipin::TrackerConfig& config) {
    json out = json::array();
    for (const auto& b : beacons) {
        double sx = 0.0, sy = 0.0;
        std::map<int, std::size_t> floors;
        std::size_t n = 0;
        for (const auto& lw : walks) {
            if (lw.walk.landmarks.empty()) continue;
            std::vector<double> times;
            for (const auto& r : lw.ble)
                if (r.mac == b.mac && r.rss_dbm >= config.ble_min_rss_dbm) times.push_back(r.t);
            for (const auto& p : survey::place_scans(lw.walk.landmarks, times).placed) {
                sx += p.where.at.x;
                sy += p.where.at.y;
                ++floors[p.where.floor];
                ++n;
            }
        }
        json row = {{"mac", b.mac.str()}, {"floor", b.floor}, {"x", b.at.x}, {"y", b.at.y}, {"strong_readings", n}};
        if (n > 0) {
            const Point c{sx / n, sy / n};
            const int floor = std::max_element(floors.begin(), floors.end(), [](const auto& a, const auto& z) { return a.second < z.second; })->first;
            row["heard_near"] = {{"floor", floor}, {"x", c.x}, {"y", c.y}};
            row["off_m"] = std::hypot(c.x - b.at.x, c.y - b.at.y);
        }
        out.push_back(row);
    }
    return out;
}

// The latest estimate at or before each scan (nullopt before the first), for the per-scan figures.
std::vector<std::optional<ipin::Fix>> at_scans(const std::vector<ipin::Fix>& estimates, const std::vector<double>& scan_t) {
    std::vector<std::optional<ipin::Fix>> out(scan_t.size());
    std::size_t j = 0;
    for (std::size_t i = 0; i < scan_t.size(); ++i) {
        while (j < estimates.size() && estimates[j].t <= scan_t[i]) ++j;
        if (j > 0) out[i] = estimates[j - 1];
    }
    return out;
}

struct Context {
    const Args& args;
    std::optional<Yardstick> ys;
    MapFloors floors;
    match::Workspace workspace;
    api::Client* client = nullptr;
    std::vector<std::optional<ipin::Fix>> scan_fixes;  // walk_pf's last walk: each scan's own fix from the live track
};

// One method on one walk: `estimates` (time order) for the POSI scoring, the per-scan answers returned.
// `answers`: the server's to the scans as read; `tracked`: those kalman and pdr fuse (sent with
// the phone's learnt offset, unless --no-offset); walk_pf's live track answers `live` (its id,
// requests, the offset the server learnt).
std::vector<std::optional<ipin::Fix>> run_method(const std::string& m, const LoadedWalk& lw,
                                                 const std::vector<std::optional<ipin::Fix>>& answers,
                                                 const std::vector<std::optional<ipin::Fix>>& tracked, Context& c,
                                                 std::vector<ipin::Fix>& estimates, json& live) {
    std::vector<std::optional<ipin::Fix>> per_scan;
    if (m == "yardstick") {
        per_scan.resize(lw.walk.scans.size());
        for (std::size_t i = 0; i < lw.walk.scans.size(); ++i) {
            const auto r = match::localize(c.ys->index, match::Query::from_scans({lw.walk.scans[i]}), match::Algorithm::knn,
                                           c.ys->options, c.workspace);
            if (r) per_scan[i] = ipin::Fix{lw.walk.scan_times[i], static_cast<int>(r->floor_id), r->at};
        }
    } else if (m == "wifi") {
        per_scan = answers;
    } else if (m == "wifi-baro") {
        const std::optional<int> start_floor =
            c.args.known_start && !lw.truth.empty() ? std::optional<int>(lw.truth.front().floor) : std::nullopt;
        return with_baro_floor(lw, answers, c.floors.baro, start_floor, estimates);
    } else if (m == "walk_pf") {
        // What a phone gets: the walk posted to a live track on the map, the server's own filter.
        ipin::ReplayOptions o;
        o.map = c.args.map;
        o.known_start = c.args.known_start;
        o.gnss = !c.args.no_gnss;
        o.ble = !c.args.no_ble;
        if (!c.args.subarea) o.fusion_options = R"({"subarea": false})";
        json track;
        std::ostringstream quiet;
        estimates = ipin::live_track(*c.client, lw, c.floors, o, track, quiet, &c.scan_fixes);
        live = {{"track", track["track"]["id"]}, {"requests", track["requests"]}, {"refused_scans", track["refused_scans"]},
                {"dropped_steps", track["dropped_steps"]}};
        if (track.contains("rss_offset_db")) live["rss_offset_db"] = track["rss_offset_db"];
        return at_scans(estimates, lw.walk.scan_times);
    } else {
        const ipin::Tracker tracker = m == "pdr" ? ipin::Tracker::pdr : ipin::Tracker::kalman;
        estimates = ipin::run_tracker(tracker, lw, tracked, c.floors, {c.args.known_start, !c.args.no_gnss, !c.args.no_ble});
        return at_scans(estimates, lw.walk.scan_times);
    }
    for (const auto& f : per_scan)
        if (f) estimates.push_back(*f);
    return per_scan;
}

void print_table(const json& out, const std::vector<std::string>& methods) {
    std::printf("%-10s %-9s %9s %9s %7s %6s %12s\n", "trial", "phone", "method", "p75_m", "mean_m", "floor", "scans_p75_m");
    auto line = [](const std::string& t, const std::string& p, const std::string& m, const json& f) {
        auto num = [](const json& v) { return v.is_number() ? v.get<double>() : NAN; };
        std::printf("%-10s %-9s %9s %9.2f %7.2f %6.2f %12.2f\n", t.c_str(), p.c_str(), m.c_str(), num(f["p75_m"]),
                    num(f["mean_m"]), num(f["floor_hit_rate"]), num(f["scans"]["p75_m"]));
    };
    for (const auto& r : out["trials"])
        for (const auto& m : methods) line(r["trial"], r["phone"], m, r["methods"][m]);
    for (const auto& m : methods) line("pooled", "", m, out["pooled"][m]);
}

std::vector<std::string> methods_of(const std::string& method) {
    if (method != "all") return {method};
    return {"yardstick", "wifi", "wifi-baro", "pdr", "kalman", "walk_pf"};
}

void run(const Args& a) {
    const std::vector<std::string> methods = methods_of(a.method);
    const bool want_yardstick = a.method == "yardstick" || a.method == "all";
    const bool want_server = a.method != "yardstick";
    const bool want_baro = want_server && a.method != "wifi";
    if (want_yardstick && a.train.empty()) throw CommandError("--method " + a.method + " needs --train GLOB (the yardstick's walks)");
    if (want_server && a.map <= 0) throw CommandError("--method " + a.method + " needs --map ID (and --server URL)");
    const auto test = ipin::load_walks(a.dir, a.trials);
    Context c{a, std::nullopt, {}, {}, nullptr, {}};
    if (want_yardstick) c.ys = yardstick(ipin::load_walks(a.dir, a.train));
    // kalman and pdr fuse the answers here; walk_pf's live track asks the server itself.
    const bool want_trackers = std::any_of(methods.begin(), methods.end(), [](const std::string& m) { return m == "pdr" || m == "kalman"; });
    if (a.no_offset && !want_trackers)
        throw CommandError("--no-offset is for pdr and kalman: walk_pf's live track learns its phone's offset itself");
    const bool learns_offset = want_trackers && !a.no_offset;
    const bool want_raw_answers = (want_trackers && !learns_offset) || std::any_of(methods.begin(), methods.end(), [](const std::string& m) {
                                      return m == "wifi" || m == "wifi-baro";
                                  });
    std::optional<api::Client> client;
    std::optional<ipin::RpFingerprints> fingerprints;
    if (want_server) {
        client.emplace(a.server.client_options());
        c.client = &*client;
        fingerprints.emplace(*client);
        c.floors = ipin::map_floors(*client, a.map, want_baro);
        if (want_baro && c.floors.baro.empty())
            throw CommandError("--method " + a.method + " needs the map's floors' elevation_m (none has one)");
    }
    std::map<std::string, ipin::Errors> pooled, pooled_scans;
    ipin::Errors pooled_scan_fixes;
    std::map<std::string, std::size_t> unanswered;
    json trials = json::array();
    for (const auto& lw : test) {
        std::cerr << "evaluating " << lw.label << " (" << lw.phone << ", " << lw.walk.scans.size() << " scans, "
                  << lw.steps.size() << " steps)\n";
        const auto truth_of_scan = ipin::scan_truth(lw.walk);
        // The server's answers to the scans as read, asked once for every method that uses them
        // (wifi, wifi-baro, and the trackers with --no-offset).
        const auto answers = want_raw_answers ? ipin::server_answers(*client, a.map, c.floors, lw) : std::vector<std::optional<ipin::Fix>>{};
        json row = {{"trial", lw.label}, {"phone", lw.phone}, {"methods", json::object()}};
        // The trackers' answers: each scan with the offset this walk's earlier scans taught.
        std::vector<std::optional<ipin::Fix>> tracked = answers;
        if (learns_offset) {
            match::DeviceOffset offset;
            tracked = ipin::server_answers(*client, a.map, c.floors, lw, &offset, &*fingerprints);
            row["offset_db"] = offset.offset_db();
            row["offset_looks"] = offset.looks();
        }
        for (const auto& m : methods) {
            std::vector<ipin::Fix> estimates, scan_est, scan_truths;
            json live;
            const auto per_scan = run_method(m, lw, answers, tracked, c, estimates, live);
            if (!live.is_null()) row["live"] = live;
            for (std::size_t i = 0; i < per_scan.size(); ++i) {
                if (!per_scan[i]) {
                    ++unanswered[m];
                    continue;
                }
                if (truth_of_scan[i]) {
                    scan_est.push_back(*per_scan[i]);
                    scan_truths.push_back(*truth_of_scan[i]);
                }
            }
            const auto at_posi = ipin::score_instants(estimates, lw.truth);
            const auto at_scans = ipin::score_pairs(scan_est, scan_truths);
            ipin::pool(pooled[m], at_posi);
            ipin::pool(pooled_scans[m], at_scans);
            json f = ipin::figures(at_posi);
            f["scans"] = ipin::figures(at_scans);
            if (m == "walk_pf") {
                // The live track's own scan fixes (matched in its subarea), at the same scans.
                std::vector<ipin::Fix> fix_est, fix_truths;
                for (std::size_t i = 0; i < c.scan_fixes.size(); ++i)
                    if (c.scan_fixes[i] && truth_of_scan[i]) fix_est.push_back(*c.scan_fixes[i]), fix_truths.push_back(*truth_of_scan[i]);
                const auto scan_fix_errors = ipin::score_pairs(fix_est, fix_truths);
                ipin::pool(pooled_scan_fixes, scan_fix_errors);
                f["scan_fixes"] = ipin::figures(scan_fix_errors);
            }
            row["methods"][m] = f;
        }
        trials.push_back(row);
    }
    json out = {{"default", methods.back()}, {"known_start", a.known_start}, {"gnss", !a.no_gnss}, {"ble", !a.no_ble}, {"offset", !a.no_offset}, {"pooled", json::object()}, {"trials", trials}};
    if (want_server) out["beacons"] = beacon_check(test, c.floors.beacons, ipin::TrackerConfig{});
    for (const auto& m : methods) {
        json f = ipin::figures(pooled[m]);
        f["scans"] = ipin::figures(pooled_scans[m]);
        f["unanswered_scans"] = unanswered[m];
        if (m == "walk_pf") f["scan_fixes"] = ipin::figures(pooled_scan_fixes);
        out["pooled"][m] = f;
    }
    if (a.json_out) {
        std::cout << out.dump() << "\n";
        return;
    }
    print_table(out, methods);
}

}  // namespace

LOCUS_COMMAND("eval-ipin", [](CLI::App& app) {
    auto& eval = locus::tools::group(app, "eval", "Measure the matchers on real data sets");
    auto* cmd = eval.add_subcommand("ipin", "Score WiFi positioning of IPIN 2023 walks as the competition does (docs/ipin-import.md)");
    auto a = std::make_shared<Args>();
    a->server.add_to(*cmd);
    cmd->add_option("DIR", a->dir, "the data set folder (with trials/)")->required();
    cmd->add_option("--trials", a->trials, "held-out walks: globs on the file names of DIR/trials (repeat: any matches)")->required();
    cmd->add_option("--train", a->train, "the yardstick's walks (a glob, as --trials)");
    cmd->add_option("--method", a->method,
                    "yardstick, wifi (the server's answer), wifi-baro (its floor from the barometer), pdr, kalman (baselines: "
                    "IMU, WiFi, barometer, GNSS and BLE fused here), walk_pf (the default: the walk posted to a live track, "
                    "the server's own filter, what a phone gets) or all (the default last)")
        ->capture_default_str()
        ->check(CLI::IsMember({"yardstick", "wifi", "wifi-baro", "pdr", "kalman", "walk_pf", "all"}));
    cmd->add_flag("--known-start", a->known_start,
                  "give the trackers (and wifi-baro's floor) the first POSI landmark's position, floor and time");
    cmd->add_flag("--no-gnss", a->no_gnss, "the trackers without the logs' GNSS fixes");
    cmd->add_flag("--no-ble", a->no_ble, "the trackers without the logs' readings of the map's BLE beacons");
    cmd->add_flag_callback("--no-subarea", [a] { a->subarea = false; },
                           "walk_pf's live tracks opened with fusion_options.subarea false: their scans matched on the whole map");
    cmd->add_flag("--no-offset", a->no_offset, "pdr's and kalman's scans sent as read, without the phone's RSS offset learnt online");
    cmd->add_option("--map", a->map, "map id (every method but the yardstick; walk_pf posts to a live track on it: give the API key, --api-key or LOCUS_API_KEY, or a phone's rate limits apply)");
    cmd->add_flag("--json", a->json_out, "one JSON object on stdout instead of the table");
    cmd->callback([a] { run(*a); });
});

}  // namespace locus_cli_eval_ipin
