#pragma once
// What the replays that post a recorded walk to a live track share (tools/ipin_replay.hpp,
// tools/putmc_live.hpp): a scan and a step as a thin client writes them in a
// POST /v1/tracks/{id}/steps body (docs/tracks.md), and posting a batch as a phone goes on when
// part of it is refused. Cost: one request per call, more when the server refuses a part.
#include <cstddef>
#include <optional>
#include <utility>

#include <nlohmann/json.hpp>

#include "locus/api/client.hpp"
#include "locus/radio_map.hpp"

namespace locus::tools {

// A scan's readings, [{type, bssid, rss}].
nlohmann::json readings_json(const Scan& scan);

// A compass azimuth (clockwise from north, rad) less `less_deg`, in [0, 360) degrees: a step's
// heading_deg.
double heading_deg(double azimuth_rad, double less_deg = 0.0);

// What posting a walk's batches took: requests sent, WiFi scans the map could not answer
// (422 no_match: posted again without them, the BLE scans beside them kept), steps sent before
// the track's filter could start (422 cannot_fuse: posted again without them).
struct PostCounts {
    std::size_t requests = 0, refused_scans = 0, dropped_steps = 0;
};

// The server's answer to `batch`, or nullopt when nothing of it was left to post; any other
// refusal passes (api::ApiError).
std::optional<nlohmann::json> post_going_on(api::Client& client, const api::TrackKey& key, nlohmann::json batch, PostCounts& counts);

// The replay's live track, closed at its end (close(), whose errors pass) or, when a request
// threw before, by the destructor (errors ignored): a track left open would count against
// the client's live tracks until its TTL.
class OpenTrack {
public:
    OpenTrack(api::Client& client, api::TrackKey key) : client_(client), key_(std::move(key)) {}
    OpenTrack(const OpenTrack&) = delete;
    OpenTrack& operator=(const OpenTrack&) = delete;
    ~OpenTrack() {
        if (!open_) return;
        try {
            client_.close_track(key_);
        } catch (...) {  // a request already failed: its error is the one to report
        }
    }
    const api::TrackKey& key() const { return key_; }
    void close() {
        open_ = false;
        client_.close_track(key_);
    }

private:
    api::Client& client_;
    api::TrackKey key_;
    bool open_ = true;
};

}  // namespace locus::tools
