#pragma once
// Posts a replayed walk's fused track to a server as a live track (`locus replay --live`), so
// the web map, the event streams and /relative can be shown with real data.
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "locus/api/client.hpp"
#include "locus/geometry.hpp"

namespace locus::tools {

struct LivePoint {
    double t_s = 0;  // seconds from the walk's start
    Point at;
};

struct LiveOptions {
    std::int64_t map_id = 0, floor_id = 0;
    std::string label;
    double speed = 1.0;     // 1: real time, 10: ten times faster, 0: all at once (the fixes dated in the past)
    double accuracy_m = 2.0;
    bool close = true;      // close the track after the last fix
};

// Opens a track, posts every point (one post per point, paced; batches of 1,000 at speed 0)
// with a heading from the move since the previous point, and answers the track's key.
api::TrackKey post_live(api::Client& client, const std::vector<LivePoint>& points, const LiveOptions& options, std::ostream& log);

}  // namespace locus::tools
