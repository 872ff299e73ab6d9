#include "ipin_walk.hpp"

#include <algorithm>
#include <numbers>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "datasets/ipin_log.hpp"
#include "floor_geo_json.hpp"
#include "ipin_venue.hpp"
#include "locus/survey/walk.hpp"

namespace locus::tools::ipin {

using nlohmann::json;

namespace {

// A map's floor as the barometric estimator takes it: level, elevation_m, and whether the floor
// has a radio map (the server cannot answer a floor without one). A floor without an elevation
// cannot be placed by pressure and is left out (nullopt).
std::optional<fusion::FloorLevel> baro_floor(api::Client& client, const api::FloorInfo& f) {
    const json stored = client.get("/v1/floors/" + std::to_string(f.id));
    const auto e = stored.find("elevation_m");
    if (e == stored.end() || !e->is_number()) return std::nullopt;
    return fusion::FloorLevel{f.level, e->get<double>(), !client.radiomaps(f.id).empty()};
}

}  // namespace

LoadedWalk load_walk(const std::string& path) {
    datasets::ipin::Log log;
    try {
        log = datasets::ipin::read_log(path);
    } catch (const datasets::ipin::LogError& e) {
        throw CommandError(e.what());
    }
    const geo::FloorToEarth frame(venue_georeference());
    LoadedWalk w;
    w.label = trial_label(path);
    w.phone = log.header.model;
    w.walk.source = path;
    w.walk.stem = w.label;
    std::size_t dropped = 0;
    w.walk.landmarks = landmarks_of_posi(
        log, [&](int, double lat, double lon) -> std::optional<Point> { return frame.to_floor({lat, lon}); }, dropped);
    for (const auto& l : w.walk.landmarks) w.truth.push_back({l.t, l.floor, l.at});
    add_wifi_scans(log, w.walk);
    w.pressure = datasets::ipin::pressure_series(log);
    w.steps = log_steps(log);
    w.gnss = log_gnss(log, [&](double lat, double lon) { return frame.to_floor({lat, lon}); });
    w.ble = log_ble(log);
    w.end_s = std::max(w.walk.scan_times.empty() ? 0.0 : w.walk.scan_times.back(), w.truth.empty() ? 0.0 : w.truth.back().t);
    return w;
}

std::vector<LoadedWalk> load_walks(const std::string& dir, const std::vector<std::string>& globs) {
    std::vector<std::string> files;
    try {
        files = trial_files(dir, globs);
    } catch (const std::runtime_error& e) {
        throw CommandError(e.what());
    }
    if (files.empty()) throw CommandError("no file of '" + dir + "/trials' matches the globs given");
    std::vector<LoadedWalk> out;
    for (const auto& path : files) out.push_back(load_walk(path));
    return out;
}

std::vector<std::optional<Fix>> scan_truth(const Walk& w) {
    std::vector<std::optional<Fix>> out(w.scans.size());
    if (w.landmarks.empty()) return out;
    const auto placed = survey::place_scans(w.landmarks, w.scan_times);
    for (const auto& p : placed.placed) out[p.scan] = Fix{p.t, p.where.floor, p.where.at};
    return out;
}

MapFloors map_floors(api::Client& client, std::int64_t map, bool want_baro) {
    const geo::FloorToEarth venue(venue_georeference());
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

std::vector<std::optional<Fix>> server_answers(api::Client& client, std::int64_t map, const MapFloors& floors, const LoadedWalk& lw,
                                               match::DeviceOffset* offset, RpFingerprints* fingerprints) {
    const geo::FloorToEarth venue(venue_georeference());
    std::vector<std::optional<Fix>> out(lw.walk.scans.size());
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
            out[i] = Fix{lw.walk.scan_times[i], it->second.level, at};
        } catch (const api::ApiError& err) {
            if (err.status() / 100 != 4) throw;  // 4xx: no answer for this scan (e.g. no AP known)
        }
    }
    return out;
}

match::Fingerprint RpFingerprints::of(const std::vector<long long>& rp_ids) {
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

std::vector<Fix> run_tracker(Tracker tracker, const LoadedWalk& lw, const std::vector<std::optional<Fix>>& answers,
                             const MapFloors& floors, const TrackerInputs& inputs) {
    const std::optional<Fix> start = inputs.known_start && !lw.truth.empty() ? std::optional<Fix>(lw.truth.front()) : std::nullopt;
    // The venue's frame is the georeference's: its +y axis at bearing_deg from true north, so
    // a compass azimuth ψ is ψ − bearing in it (magnetic declination, ~3° here, ignored).
    TrackerConfig config;
    config.compass_offset_rad = -venue_georeference().bearing_deg * std::numbers::pi / 180.0;
    const std::vector<BeaconFix> ble = inputs.ble ? beacon_fixes(lw.ble, floors.beacons, config) : std::vector<BeaconFix>{};
    TrackInput in{lw.steps, lw.pressure, lw.walk.scan_times, answers, lw.end_s, start, {}, ble};
    if (inputs.gnss) in.gnss = lw.gnss;
    return track(tracker, in, floors.baro, config);
}

}  // namespace locus::tools::ipin
