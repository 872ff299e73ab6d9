#include "ipin_replay.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "command_registry.hpp"
#include "ipin_eval.hpp"
#include "ipin_venue.hpp"
#include "ipin_walk.hpp"
#include "live_post.hpp"

namespace locus::tools::ipin {

namespace {

using nlohmann::json;

json parse_fusion_options(const std::string& text) {
    json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object())
        throw CommandError("--fusion-options takes a JSON object, e.g. '{\"step_scale\": 1.2}'");
    return j;
}

// The map's floor of `level` (its id and frame), the first one when several buildings have it.
const std::pair<const long long, MapFloors::Floor>* floor_of_level(const MapFloors& floors, int level) {
    for (const auto& entry : floors.by_id)
        if (entry.second.level == level) return &entry;
    return nullptr;
}

}  // namespace

// The log as a thin client posts it: at each WiFi scan, the steps, pressure samples, GNSS fixes
// and BLE readings (as BLE scans) since the last request, then the scan (its answer is the
// radio fix the server's filter needs to start); a last request with what follows the last
// scan. The walk's clock is moved onto Unix time so that the walk ends now (the server refuses
// fixes from the future and older than it keeps). A scan no RP hears (422 no_match) is posted
// again without it, steps before the filter could start (422 cannot_fuse) are dropped, as a
// phone would go on.

std::vector<Fix> live_track(api::Client& client, const LoadedWalk& lw, const MapFloors& floors, const ReplayOptions& o, json& out,
                            std::ostream& log, std::vector<std::optional<Fix>>* scan_fixes) {
    if (scan_fixes) scan_fixes->assign(lw.walk.scans.size(), std::nullopt);
    const geo::FloorToEarth venue(venue_georeference());
    const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    double last_t = lw.end_s;
    if (!lw.steps.empty()) last_t = std::max(last_t, lw.steps.back().t_s);
    if (!lw.pressure.empty()) last_t = std::max(last_t, lw.pressure.back().t_s);
    if (!lw.gnss.empty()) last_t = std::max(last_t, lw.gnss.back().t);
    if (!lw.ble.empty()) last_t = std::max(last_t, lw.ble.back().t);
    const double base = std::floor(now - last_t - 1.0);
    // The track is opened as a phone opens it (the server's defaults), or with the options given.
    json body = {{"map_id", o.map}, {"label", "replay " + lw.label + " (thin)"}};
    if (!o.fusion_options.empty()) body["fusion_options"] = parse_fusion_options(o.fusion_options);
    // A step's heading is the compass azimuth as the phone reads it (clockwise from north), the
    // server turning it into the floor's frame (docs/tracks.md), unless the options say the
    // headings are the floor's already (rotation_sigma_deg): then the azimuth less the floor's
    // bearing (the floors `locus import ipin` makes share one georeference).
    double bearing_deg = 0.0;
    if (body.contains("fusion_options") && body["fusion_options"].contains("rotation_sigma_deg"))
        for (const auto& [id, f] : floors.by_id)
            if (f.frame) {
                bearing_deg = f.frame->georeference().bearing_deg;
                break;
            }
    const json opened = client.post("/v1/tracks", body);
    OpenTrack track(client, {opened.at("id").get<std::int64_t>(), opened.at("token").get<std::string>()});
    const api::TrackKey& key = track.key();
    out["track"] = {{"id", key.id}, {"token", key.token}};
    if (body.contains("fusion_options")) out["fusion_options"] = body["fusion_options"];
    std::vector<Fix> estimates;
    // A fix of the answer in the venue's frame, on the log's clock (none: not a floor of the map).
    auto venue_fix = [&](const json& f) -> std::optional<Fix> {
        const auto it = floors.by_id.find(f.at("floor_id").get<long long>());
        if (it == floors.by_id.end()) return std::nullopt;
        const Point at{f.at("x").get<double>(), f.at("y").get<double>()};
        return Fix{f.at("t").get<double>() - base, it->second.level, it->second.frame ? venue.to_floor(it->second.frame->to_geodetic(at)) : at};
    };
    auto take = [&](const json& answer, std::optional<std::size_t> scan) {
        for (const auto& f : answer.value("fused", json::array()))
            if (const auto e = venue_fix(f)) estimates.push_back(*e);
        if (answer.contains("rss_offset_db")) out["rss_offset_db"] = answer["rss_offset_db"];
        // The WiFi scan's: the first at its t (a BLE scan at the same t is posted after it).
        if (scan && scan_fixes)
            for (const auto& f : answer.value("scan_fixes", json::array()))
                if (std::abs(f.at("t").get<double>() - (base + lw.walk.scan_times[*scan])) < 1e-6) {
                    (*scan_fixes)[*scan] = venue_fix(f);
                    break;
                }
    };
    PostCounts counts;
    auto post = [&](json batch, std::optional<std::size_t> scan = std::nullopt) {
        if (const auto answer = post_going_on(client, key, std::move(batch), counts)) take(*answer, scan);
    };
    if (o.known_start && !lw.truth.empty()) {
        const Fix& s = lw.truth.front();
        if (const auto* f = floor_of_level(floors, s.floor)) {
            const Point at = f->second.frame ? f->second.frame->to_floor(venue.to_geodetic(s.at)) : s.at;
            post({{"fixes", json::array({{{"t", base + s.t}, {"floor_id", f->first}, {"x", at.x}, {"y", at.y}, {"accuracy_m", 0.5}}})}});
        }
    }
    std::size_t step = 0, pressure = 0, gnss = 0, ble = 0;
    auto until = [&](double t_end, std::optional<std::size_t> scan) {
        json batch = json::object();
        json steps = json::array(), pres = json::array(), fixes = json::array();
        for (; step < lw.steps.size() && lw.steps[step].t_s <= t_end; ++step)
            steps.push_back({{"t", base + lw.steps[step].t_s},
                             {"length_m", lw.steps[step].length_m},
                             {"heading_deg", heading_deg(lw.steps[step].azimuth_rad, bearing_deg)}});
        for (; pressure < lw.pressure.size() && lw.pressure[pressure].t_s <= t_end; ++pressure)
            pres.push_back({{"t", base + lw.pressure[pressure].t_s}, {"hpa", lw.pressure[pressure].hpa}});
        for (; gnss < lw.gnss.size() && lw.gnss[gnss].t <= t_end; ++gnss) {
            if (!o.gnss) continue;
            const geo::LatLon ll = venue.to_geodetic(lw.gnss[gnss].at);
            fixes.push_back({{"t", base + lw.gnss[gnss].t}, {"lat", ll.lat}, {"lon", ll.lon}, {"accuracy_m", lw.gnss[gnss].accuracy_m}});
        }
        if (!steps.empty()) batch["steps"] = std::move(steps);
        if (!pres.empty()) batch["pressure"] = std::move(pres);
        if (!fixes.empty()) batch["gnss"] = std::move(fixes);
        // The WiFi scan, and the BLE readings since the last request as the phone's BLE scans,
        // in time order, the WiFi scan first at equal t.
        std::vector<std::pair<double, json>> scans;
        if (scan) {
            scans.emplace_back(lw.walk.scan_times[*scan],
                               json{{"t", base + lw.walk.scan_times[*scan]}, {"readings", readings_json(lw.walk.scans[*scan])}});
        }
        // A phone gathers its BLE results a second at a time (each scan posted is a localization):
        // one scan per second of readings, stamped with its last reading's time.
        std::optional<std::size_t> ble_scan;
        double ble_from = 0.0;  // the open BLE scan's first reading's time
        for (; ble < lw.ble.size() && lw.ble[ble].t <= t_end; ++ble) {
            if (!o.ble) continue;
            const double t = lw.ble[ble].t;
            const json reading = {{"type", "ble"}, {"bssid", lw.ble[ble].mac.str()}, {"rss", lw.ble[ble].rss_dbm}};
            if (ble_scan && t - ble_from < 1.0) {
                scans[*ble_scan].first = t;
                scans[*ble_scan].second["t"] = base + t;
                scans[*ble_scan].second["readings"].push_back(reading);
                continue;
            }
            ble_scan = scans.size();
            ble_from = t;
            scans.emplace_back(t, json{{"t", base + t}, {"readings", json::array({reading})}});
        }
        std::stable_sort(scans.begin(), scans.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        if (!scans.empty()) {
            batch["scans"] = json::array();
            for (auto& [t, j] : scans) batch["scans"].push_back(std::move(j));
        }
        if (!batch.empty()) post(std::move(batch), scan);
    };
    for (std::size_t i = 0; i < lw.walk.scans.size(); ++i) until(lw.walk.scan_times[i], i);
    until(std::numeric_limits<double>::infinity(), std::nullopt);  // what follows the last scan
    track.close();
    out["requests"] = counts.requests;
    out["refused_scans"] = counts.refused_scans;
    out["dropped_steps"] = counts.dropped_steps;
    log << "live track " << key.id << ": " << counts.requests << " requests, " << estimates.size() << " fused fixes\n";
    return estimates;
}

json replay_log(api::Client& client, const ReplayOptions& o, std::ostream& log) {
    const bool live = o.rule == "walk_pf" || o.rule == "thin";
    const bool tracker = o.rule == "kalman" || o.rule == "pdr";
    if (!live && !tracker && o.rule != "wifi")
        throw CommandError("unknown --rule '" + o.rule + "' for a logfile (walk_pf, the same as thin; kalman, pdr, wifi)");
    const LoadedWalk lw = load_walk(o.file);
    const MapFloors floors = map_floors(client, o.map, tracker);
    json out = {{"file", o.file}, {"format", "ipin"},    {"map", o.map},
                {"rule", o.rule}, {"phone", lw.phone},   {"known_start", o.known_start},
                {"landmarks", lw.truth.size()}};
    std::vector<Fix> estimates;
    if (live) {
        estimates = live_track(client, lw, floors, o, out, log);
    } else if (o.rule == "wifi") {
        for (const auto& a : server_answers(client, o.map, floors, lw))
            if (a) estimates.push_back(*a);
    } else {
        match::DeviceOffset offset;
        RpFingerprints fingerprints(client);
        const auto answers = o.offset ? server_answers(client, o.map, floors, lw, &offset, &fingerprints) : server_answers(client, o.map, floors, lw);
        if (o.offset) out["offset_db"] = offset.offset_db();
        estimates = run_tracker(o.rule == "pdr" ? Tracker::pdr : Tracker::kalman, lw, answers, floors, {o.known_start, o.gnss, o.ble});
    }
    const geo::FloorToEarth venue(venue_georeference());
    json list = json::array();
    for (const auto& e : estimates) {
        const geo::LatLon ll = venue.to_geodetic(e.at);
        list.push_back({{"t", e.t}, {"floor", e.floor}, {"x", e.at.x}, {"y", e.at.y}, {"lat", ll.lat}, {"lon", ll.lon}});
    }
    out["estimates"] = std::move(list);
    if (!lw.truth.empty()) {
        const Errors e = score_instants(estimates, lw.truth);
        out["score"] = figures(e);
        out["score"]["errors"] = e.errors;  // per landmark, for pooling walks
    }
    return out;
}

}  // namespace locus::tools::ipin
