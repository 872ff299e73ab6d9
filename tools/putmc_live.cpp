#include "putmc_live.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "locus/api/error.hpp"
#include "putmc_thin.hpp"

namespace locus::tools::walks {

using nlohmann::json;

LiveWalk live_walk(api::Client& client, std::int64_t map_id, const datasets::putmc::Walk& walk) {
    const std::vector<ThinBatch> batches = thin_batches(walk);
    LiveWalk out;
    out.at_scan.resize(batches.size());
    if (batches.empty()) return out;
    const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    const double base = std::floor(now - batches.back().t_s - 1.0);
    const api::TrackKey key = client.open_track(map_id, "eval walks " + walk.name).key;
    out.track_id = key.id;
    out.token = key.token;
    std::optional<Point> latest;
    for (std::size_t i = 0; i < batches.size(); ++i) {
        const ThinBatch& b = batches[i];
        json batch = json::object();
        if (!b.steps.empty()) {
            json steps = json::array();
            for (const auto& s : b.steps) {
                double heading = std::fmod(s.azimuth_rad * 180.0 / std::numbers::pi, 360.0);
                if (heading < 0.0) heading += 360.0;
                if (!(heading < 360.0)) heading = 0.0;
                steps.push_back({{"t", base + s.t_s}, {"length_m", s.length_m}, {"heading_deg", heading}});
            }
            batch["steps"] = std::move(steps);
        }
        if (!b.scan->readings.empty()) {
            json readings = json::array();
            for (const auto& r : b.scan->readings) readings.push_back({{"type", r.type}, {"bssid", r.bssid.str()}, {"rss", r.rss}});
            batch["scans"] = json::array({{{"t", base + b.t_s}, {"readings", std::move(readings)}}});
        }
        while (!batch.empty()) {
            try {
                ++out.requests;
                const json answer = client.post_steps(key, batch);
                const json& fused = answer.at("fused");
                if (!fused.empty()) latest = Point{fused.back().at("x").get<double>(), fused.back().at("y").get<double>()};
                break;
            } catch (const api::ApiError& e) {
                if (e.code() == "no_match" && batch.contains("scans")) {
                    ++out.refused_scans;
                    batch.erase("scans");
                } else if (e.code() == "cannot_fuse" && batch.contains("steps")) {
                    out.dropped_steps += batch["steps"].size();
                    batch.erase("steps");
                } else {
                    throw;
                }
            }
        }
        out.at_scan[i] = latest;
    }
    client.close_track(key);
    return out;
}

}  // namespace locus::tools::walks
