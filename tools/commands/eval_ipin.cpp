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
// at each scan and every 0.5 s between (the last answer's position, the floor then); `pdr`,
// `kalman` and `walk_pf` (the default), the walk's IMU fused with those answers, the barometer, GNSS (not with --no-gnss) and the
// map's BLE beacons (not with --no-ble), estimates
// every 0.5 s from the file's start (tools/ipin_track.hpp). Causal: an estimate at t uses only
// the samples and answers at or before t. --known-start gives the trackers (and wifi-baro's
// barometer) the first POSI landmark, as the competition gave its scoring walks' start. The
// server's answers are brought from their floor's frame into the venue's through the floors'
// georeferences (the same frame for every floor `locus import ipin` makes).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/ipin_log.hpp"
#include "floor_geo_json.hpp"
#include "ipin_eval.hpp"
#include "ipin_track.hpp"
#include "ipin_venue.hpp"
#include "locus/motion/fusion/baro_floor.hpp"
#include "locus/motion/fusion/walk_runner.hpp"
#include "locus/match/device_offset.hpp"
#include "locus/match/localize.hpp"
#include "survey_connect.hpp"
#include "walk_survey.hpp"

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
    bool json_out = false;
};

struct LoadedWalk {
    std::string label, phone;
    Walk walk;
    std::vector<ipin::Fix> truth;  // POSI instants on the venue's floors
    std::vector<datasets::ipin::PressureSample> pressure;
    std::vector<ipin::ImuStep> steps;
    std::vector<ipin::GnssFix> gnss;
    std::vector<ipin::BleReading> ble;
    double end_s = 0.0;  // the last scan or POSI instant: the trackers' ticks run to here
};

std::vector<LoadedWalk> load(const std::string& dir, const std::vector<std::string>& globs) {
    std::vector<std::string> files;
    try {
        files = ipin::trial_files(dir, globs);
    } catch (const std::runtime_error& e) {
        throw CommandError(e.what());
    }
    if (files.empty()) throw CommandError("no file of '" + dir + "/trials' matches the globs given");
    const geo::FloorToEarth frame(ipin::venue_georeference());
    std::vector<LoadedWalk> out;
    for (const auto& path : files) {
        datasets::ipin::Log log;
        try {
            log = datasets::ipin::read_log(path);
        } catch (const datasets::ipin::LogError& e) {
            throw CommandError(e.what());
        }
        LoadedWalk w;
        w.label = ipin::trial_label(path);
        w.phone = log.header.model;
        w.walk.source = path;
        w.walk.stem = w.label;
        std::size_t dropped = 0;
        w.walk.landmarks = landmarks_of_posi(
            log, [&](int, double lat, double lon) -> std::optional<Point> { return frame.to_floor({lat, lon}); }, dropped);
        for (const auto& l : w.walk.landmarks) w.truth.push_back({l.t, l.floor, l.at});
        add_wifi_scans(log, w.walk);
        w.pressure = datasets::ipin::pressure_series(log);
        w.steps = ipin::log_steps(log);
        w.gnss = ipin::log_gnss(log, [&](double lat, double lon) { return frame.to_floor({lat, lon}); });
        w.ble = ipin::log_ble(log);
        w.end_s = std::max(w.walk.scan_times.empty() ? 0.0 : w.walk.scan_times.back(), w.truth.empty() ? 0.0 : w.truth.back().t);
        out.push_back(std::move(w));
    }
    return out;
}

// Where each scan of a walk is, by the walking survey; nullopt where it is not placed.
std::vector<std::optional<ipin::Fix>> scan_truth(const Walk& w) {
    std::vector<std::optional<ipin::Fix>> out(w.scans.size());
    if (w.landmarks.empty()) return out;
    const auto placed = survey::place_scans(w.landmarks, w.scan_times);
    for (const auto& p : placed.placed) out[p.scan] = ipin::Fix{p.t, p.where.floor, p.where.at};
    return out;
}

// The yardstick's index over the training walks' placed scans, one RP per scan.
struct Yardstick {
    match::Index index;
    match::Options options;
};

Yardstick yardstick(const std::vector<LoadedWalk>& train) {
    std::vector<match::IndexedRp> rps;
    double min_rss = 0.0;
    for (const auto& lw : train) {
        const auto truth = scan_truth(lw.walk);
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

// A map's floor as the barometric estimator takes it: level, elevation_m, and whether the floor
// has a radio map (the server cannot answer a floor without one). A floor without an elevation
// cannot be placed by pressure and is left out (nullopt).
std::optional<fusion::FloorLevel> baro_floor(api::Client& client, const api::FloorInfo& f) {
    const json stored = client.get("/v1/floors/" + std::to_string(f.id));
    const auto e = stored.find("elevation_m");
    if (e == stored.end() || !e->is_number()) return std::nullopt;
    return fusion::FloorLevel{f.level, e->get<double>(), !client.radiomaps(f.id).empty()};
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

// The map's floors as the server holds them: level, the floor's own frame (to bring its
// answers into the venue's one frame through the Earth) and, for the barometer, its elevation.
struct MapFloors {
    struct Floor {
        int level = 0;
        std::optional<geo::FloorToEarth> frame;
    };
    std::map<long long, Floor> by_id;
    std::vector<fusion::FloorLevel> baro;
    std::vector<ipin::Beacon> beacons;  // the floors' BLE transmitters, in the venue's frame
};

MapFloors map_floors(api::Client& client, std::int64_t map, bool want_baro) {
    const geo::FloorToEarth venue(ipin::venue_georeference());
    MapFloors out;
    for (const auto& b : client.buildings(map))
        for (const auto& f : client.floors(b.id)) {
            MapFloors::Floor fl{f.level, std::nullopt};
            if (const auto ref = georeference_of(client.get("/v1/floors/" + std::to_string(f.id)))) fl.frame.emplace(*ref);
            for (const auto& t : client.list_all("/v1/floors/" + std::to_string(f.id) + "/transmitters")) {
                if (t.value("type", "") != "ble" || !t.contains("x") || !t.contains("y")) continue;
                const Point at{t.at("x").get<double>(), t.at("y").get<double>()};
                out.beacons.push_back({Bssid(t.value("bssid", "")), f.level, fl.frame ? venue.to_floor(fl.frame->to_geodetic(at)) : at});
            }
            out.by_id[f.id] = fl;
            if (want_baro)
                if (const auto level = baro_floor(client, f)) out.baro.push_back(*level);
        }
    if (out.by_id.empty()) throw CommandError("map " + std::to_string(map) + " has no floor");
    return out;
}

// The RPs' fingerprints (mean RSS by AP), read from the server once each.
class RpFingerprints {
public:
    explicit RpFingerprints(api::Client& client) : client_(client) {}
    // The mean of the RPs' means, AP by AP (over the RPs that hear it).
    match::Fingerprint of(const std::vector<long long>& rp_ids) {
        std::unordered_map<std::string, std::pair<double, int>> sum;
        for (const long long id : rp_ids) {
            auto it = cache_.find(id);
            if (it == cache_.end()) {
                match::Fingerprint fp;
                for (const auto& m : client_.rp(id).measurements) fp[m.bssid.str()] = m.stats.mean;
                it = cache_.emplace(id, std::move(fp)).first;
            }
            for (const auto& [ap, mean] : it->second) {
                sum[ap].first += mean;
                ++sum[ap].second;
            }
        }
        match::Fingerprint out;
        for (const auto& [ap, s] : sum) out[ap] = s.first / s.second;
        return out;
    }

private:
    api::Client& client_;
    std::unordered_map<long long, match::Fingerprint> cache_;
};

// The server's answer to each scan of a walk, in the venue's frame; nullopt where it had none.
// With `offset`, each scan is sent with the phone's offset learnt from the scans before it
// (match::DeviceOffset, each answer's RPs the fingerprint it is compared with).
std::vector<std::optional<ipin::Fix>> server_answers(api::Client& client, std::int64_t map, const MapFloors& floors,
                                                     const LoadedWalk& lw, match::DeviceOffset* offset = nullptr,
                                                     RpFingerprints* fingerprints = nullptr) {
    const geo::FloorToEarth venue(ipin::venue_georeference());
    std::vector<std::optional<ipin::Fix>> out(lw.walk.scans.size());
    for (std::size_t i = 0; i < lw.walk.scans.size(); ++i) {
        api::LocalizeRequest req;
        req.scans = {lw.walk.scans[i]};
        if (offset)
            for (auto& r : req.scans.front()) r.rss += offset->offset_db();
        try {
            const auto r = client.localize_map(map, req);
            if (offset && fingerprints && !r.rp_ids.empty()) offset->add(lw.walk.scans[i], fingerprints->of(r.rp_ids));
            const auto it = floors.by_id.find(r.floor_id);
            if (it == floors.by_id.end()) continue;
            const Point at = it->second.frame ? venue.to_floor(it->second.frame->to_geodetic(r.at)) : r.at;
            out[i] = ipin::Fix{lw.walk.scan_times[i], it->second.level, at};
        } catch (const api::ApiError& err) {
            if (err.status() / 100 != 4) throw;  // 4xx: no answer for this scan (e.g. no AP known)
        }
    }
    return out;
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
};

// One method on one walk: `estimates` (time order) for the POSI scoring, the per-scan answers returned.
// `answers`: the server's to the scans as read; `tracked`: those the trackers fuse (sent with
// the phone's learnt offset, unless --no-offset).
std::vector<std::optional<ipin::Fix>> run_method(const std::string& m, const LoadedWalk& lw,
                                                 const std::vector<std::optional<ipin::Fix>>& answers,
                                                 const std::vector<std::optional<ipin::Fix>>& tracked, Context& c,
                                                 std::vector<ipin::Fix>& estimates) {
    const std::optional<ipin::Fix> start =
        c.args.known_start && !lw.truth.empty() ? std::optional<ipin::Fix>(lw.truth.front()) : std::nullopt;
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
        return with_baro_floor(lw, answers, c.floors.baro, start ? std::optional<int>(start->floor) : std::nullopt, estimates);
    } else {
        // The venue's frame is the georeference's: its +y axis at bearing_deg from true north, so
        // a compass azimuth ψ is ψ − bearing in it (magnetic declination, ~3° here, ignored).
        ipin::TrackerConfig config;
        config.compass_offset_rad = -ipin::venue_georeference().bearing_deg * std::numbers::pi / 180.0;
        const std::vector<ipin::BeaconFix> ble =
            c.args.no_ble ? std::vector<ipin::BeaconFix>{} : ipin::beacon_fixes(lw.ble, c.floors.beacons, config);
        ipin::TrackInput in{lw.steps, lw.pressure, lw.walk.scan_times, tracked, lw.end_s, start, {}, ble};
        if (!c.args.no_gnss) in.gnss = lw.gnss;
        const ipin::Tracker tracker = m == "pdr" ? ipin::Tracker::pdr : m == "kalman" ? ipin::Tracker::kalman : ipin::Tracker::walk_pf;
        estimates = ipin::track(tracker, in, c.floors.baro, config);
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
    const auto test = load(a.dir, a.trials);
    Context c{a, std::nullopt, {}, {}};
    if (want_yardstick) c.ys = yardstick(load(a.dir, a.train));
    const bool want_trackers = std::any_of(methods.begin(), methods.end(), [](const std::string& m) {
        return m == "pdr" || m == "kalman" || m == "walk_pf";
    });
    const bool learns_offset = want_trackers && !a.no_offset;
    const bool want_raw_answers = want_server && (!learns_offset || std::any_of(methods.begin(), methods.end(), [](const std::string& m) {
                                                      return m == "wifi" || m == "wifi-baro";
                                                  }));
    std::optional<api::Client> client;
    std::optional<RpFingerprints> fingerprints;
    if (want_server) {
        client.emplace(a.server.client_options());
        fingerprints.emplace(*client);
        c.floors = map_floors(*client, a.map, want_baro);
        if (want_baro && c.floors.baro.empty())
            throw CommandError("--method " + a.method + " needs the map's floors' elevation_m (none has one)");
    }
    std::map<std::string, ipin::Errors> pooled, pooled_scans;
    std::map<std::string, std::size_t> unanswered;
    json trials = json::array();
    for (const auto& lw : test) {
        std::cerr << "evaluating " << lw.label << " (" << lw.phone << ", " << lw.walk.scans.size() << " scans, "
                  << lw.steps.size() << " steps)\n";
        const auto truth_of_scan = scan_truth(lw.walk);
        // The server's answers to the scans as read, asked once for every method that uses them
        // (wifi, wifi-baro, and the trackers with --no-offset).
        const auto answers = want_raw_answers ? server_answers(*client, a.map, c.floors, lw) : std::vector<std::optional<ipin::Fix>>{};
        json row = {{"trial", lw.label}, {"phone", lw.phone}, {"methods", json::object()}};
        // The trackers' answers: each scan with the offset this walk's earlier scans taught.
        std::vector<std::optional<ipin::Fix>> tracked = answers;
        if (learns_offset) {
            match::DeviceOffset offset;
            tracked = server_answers(*client, a.map, c.floors, lw, &offset, &*fingerprints);
            row["offset_db"] = offset.offset_db();
            row["offset_looks"] = offset.looks();
        }
        for (const auto& m : methods) {
            std::vector<ipin::Fix> estimates, scan_est, scan_truths;
            const auto per_scan = run_method(m, lw, answers, tracked, c, estimates);
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
    a->server.add_to(*cmd, false);
    cmd->add_option("DIR", a->dir, "the data set folder (with trials/)")->required();
    cmd->add_option("--trials", a->trials, "held-out walks: globs on the file names of DIR/trials (repeat: any matches)")->required();
    cmd->add_option("--train", a->train, "the yardstick's walks (a glob, as --trials)");
    cmd->add_option("--method", a->method,
                    "yardstick, wifi (the server's answer), wifi-baro (its floor from the barometer), pdr, kalman, walk_pf "
                    "(the trackers: IMU, WiFi, barometer, GNSS and BLE; walk_pf the default) or all (the default last)")
        ->capture_default_str()
        ->check(CLI::IsMember({"yardstick", "wifi", "wifi-baro", "pdr", "kalman", "walk_pf", "all"}));
    cmd->add_flag("--known-start", a->known_start,
                  "give the trackers (and wifi-baro's floor) the first POSI landmark's position, floor and time");
    cmd->add_flag("--no-gnss", a->no_gnss, "the trackers without the logs' GNSS fixes");
    cmd->add_flag("--no-ble", a->no_ble, "the trackers without the logs' readings of the map's BLE beacons");
    cmd->add_flag("--no-offset", a->no_offset, "the trackers' scans sent as read, without the phone's RSS offset learnt online");
    cmd->add_option("--map", a->map, "map id (for wifi and wifi-baro)");
    cmd->add_flag("--json", a->json_out, "one JSON object on stdout instead of the table");
    cmd->callback([a] { run(*a); });
});
