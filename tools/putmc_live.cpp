#include "putmc_live.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "putmc_thin.hpp"

namespace locus::tools::walks {

using nlohmann::json;

LiveWalk live_walk(api::Client& client, std::int64_t map_id, const datasets::putmc::Walk& walk, bool subarea) {
    const std::vector<ThinBatch> batches = thin_batches(walk);
    LiveWalk out;
    out.at_scan.resize(batches.size());
    out.scan_fix.resize(batches.size());
    if (batches.empty()) return out;
    const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    const double base = std::floor(now - batches.back().t_s - 1.0);
    json open = {{"map_id", map_id}, {"label", "eval walks " + walk.name}};
    if (!subarea) open["fusion_options"] = {{"subarea", false}};
    const json opened = client.post("/v1/tracks", open);
    OpenTrack track(client, {opened.at("id").get<std::int64_t>(), opened.at("token").get<std::string>()});
    const api::TrackKey& key = track.key();
    out.track_id = key.id;
    out.token = key.token;
    std::optional<Point> latest;
    for (std::size_t i = 0; i < batches.size(); ++i) {
        const ThinBatch& b = batches[i];
        json batch = json::object();
        if (!b.steps.empty()) {
            json steps = json::array();
            for (const auto& s : b.steps)
                steps.push_back({{"t", base + s.t_s}, {"length_m", s.length_m}, {"heading_deg", heading_deg(s.azimuth_rad)}});
            batch["steps"] = std::move(steps);
        }
        if (!b.scan->readings.empty())
            batch["scans"] = json::array({{{"t", base + b.t_s}, {"readings", readings_json(b.scan->readings)}}});
        if (const auto answer = post_going_on(client, key, std::move(batch), out.posted)) {
            const json& fused = answer->at("fused");
            if (!fused.empty()) latest = Point{fused.back().at("x").get<double>(), fused.back().at("y").get<double>()};
            if (const auto s = answer->find("scan_fixes"); s != answer->end() && !s->empty())
                out.scan_fix[i] = Point{s->back().at("x").get<double>(), s->back().at("y").get<double>()};
        }
        out.at_scan[i] = latest;
    }
    track.close();
    return out;
}

}  // namespace locus::tools::walks
