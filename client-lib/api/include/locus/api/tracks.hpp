#pragma once
// Live tracks as the REST client sees them (POST /v1/tracks and the routes under it).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace locus::api {

struct TrackFix {
    double t = 0;  // Unix seconds
    std::int64_t floor_id = 0;
    double x = 0, y = 0, accuracy_m = 0;
    std::optional<double> heading_deg;  // clockwise from the floor's +y axis
};

// A track and a token that opens it (`X-Track-Token`).
struct TrackKey {
    std::int64_t id = 0;
    std::string token;
};

struct OpenedTrack {
    TrackKey key;  // the owner's token: keep it, the server shows it once
    double ttl_s = 0, retention_s = 0;
};

struct TrackPosted {
    std::int64_t stored = 0, duplicates = 0;
    std::optional<TrackFix> latest;
};

struct TrackState {
    std::int64_t id = 0, map_id = 0;
    std::string label, state;  // "live" or "closed"
    std::optional<TrackFix> latest;
    std::vector<TrackFix> trail;  // oldest first
};

struct TrackShare {
    std::int64_t id = 0;
    TrackKey key;  // the track's id with the share token
};

struct TrackPosition {
    std::int64_t track_id = 0;
    std::string label;
    TrackFix fix;
    double age_s = 0;
};

}  // namespace locus::api
