#include "live_post.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "locus/api/error.hpp"

namespace locus::tools {

using nlohmann::json;

json readings_json(const Scan& scan) {
    json out = json::array();
    for (const auto& r : scan) out.push_back({{"type", r.type}, {"bssid", r.bssid.str()}, {"rss", r.rss}});
    return out;
}

double heading_deg(double azimuth_rad, double less_deg) {
    double h = std::fmod(azimuth_rad * 180.0 / std::numbers::pi - less_deg, 360.0);
    if (h < 0.0) h += 360.0;
    return h < 360.0 ? h : 0.0;
}

std::optional<json> post_going_on(api::Client& client, const api::TrackKey& key, json batch, PostCounts& counts) {
    while (!batch.empty()) {
        try {
            ++counts.requests;
            return client.post_steps(key, batch);
        } catch (const api::ApiError& e) {
            if (e.code() == "no_match" && batch.contains("scans")) {
                // The WiFi scans the map cannot answer go; the BLE scans beside them stay.
                json kept = json::array();
                for (auto& sc : batch["scans"]) {
                    const bool ble = std::all_of(sc["readings"].begin(), sc["readings"].end(),
                                                 [](const json& r) { return r.value("type", "wifi") == "ble"; });
                    if (ble) kept.push_back(std::move(sc));
                    else ++counts.refused_scans;
                }
                if (kept.empty()) batch.erase("scans");
                else if (kept.size() == batch["scans"].size()) throw;  // BLE scans alone refused: not ours to drop
                else batch["scans"] = std::move(kept);
            } else if (e.code() == "cannot_fuse" && batch.contains("steps")) {
                counts.dropped_steps += batch["steps"].size();
                batch.erase("steps");
            } else {
                throw;
            }
        }
    }
    return std::nullopt;
}

}  // namespace locus::tools
