#include "tracks/track_anchors.hpp"

#include <algorithm>

namespace locus::tracks {

std::shared_ptr<const FloorAnchors> floor_anchors(const transmitters::KnownTransmitters& known) {
    auto out = std::make_shared<FloorAnchors>();
    for (const auto& [key, k] : known.by_key) out->by_floor[k.floor_id].push_back({key, k.tx});
    return out;
}

std::vector<fusion::AnchorReading> anchor_readings(const transmitters::KnownTransmitters& known, const match::Query& query, double t) {
    std::vector<fusion::AnchorReading> out;
    for (const auto& ap : query.aps)
        if (const std::string key = transmitters::transmitter_key(ap.type, ap.bssid); known.by_key.count(key)) out.push_back({key, t, ap.rss});
    if (out.size() > kMaxEkfReadings) {
        // Strongest first; ties by id, so the kept set does not depend on the scan's order.
        std::sort(out.begin(), out.end(), [](const fusion::AnchorReading& a, const fusion::AnchorReading& b) {
            return a.rss != b.rss ? a.rss > b.rss : a.anchor_id < b.anchor_id;
        });
        out.resize(kMaxEkfReadings);
    }
    return out;
}

}  // namespace locus::tracks
