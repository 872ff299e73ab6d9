#include "http/track_anchors.hpp"

namespace locus::http {

std::shared_ptr<const tracks::FloorAnchors> floor_anchors(const KnownTransmitters& known) {
    auto out = std::make_shared<tracks::FloorAnchors>();
    for (const auto& [key, k] : known.by_key) out->by_floor[k.floor_id].push_back({key, k.tx});
    return out;
}

std::vector<fusion::AnchorReading> anchor_readings(const KnownTransmitters& known, const match::Query& query, double t) {
    std::vector<fusion::AnchorReading> out;
    for (const auto& ap : query.aps)
        if (const std::string key = transmitter_key(ap.type, ap.bssid); known.by_key.count(key)) out.push_back({key, t, ap.rss});
    return out;
}

}  // namespace locus::http
