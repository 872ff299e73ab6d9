#pragma once
// What tracks::Service takes and answers (docs/tracks.md): a track's state and info, the fixes
// posted and shares made, the refusals, and what an event stream is to write next. Plain values.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tracks/fix.hpp"
#include "tracks/fusion_method.hpp"
#include "tracks/fusion_options.hpp"

namespace locus::tracks {

enum class State { live, closed, gone };
const char* state_name(State s);

// Why a request on a track is refused; the HTTP layer gives each its status.
// busy: the server's shared limits (streams, live tracks); too_many_tracks: every track slot
// is held by a live track; too_many_streams: this track's own stream limit;
// client_live_tracks, client_streams: one client's share of the shared limits.
enum class Reason { forbidden, gone, closed, busy, full, too_many_tracks, too_many_streams, client_live_tracks, client_streams };
struct Refused : std::runtime_error {
    Reason reason;
    double retry_after_s = 0;  // when known: seconds until the refusal may be lifted
    Refused(Reason r, const std::string& what, double retry_after = 0) : std::runtime_error(what), reason(r), retry_after_s(retry_after) {}
};

enum class Access { owner, share };

struct TrackInfo {
    std::int64_t id = 0, map_id = 0;
    std::string label;
    State state = State::live;
    double created_at = 0, last_fix_at = 0;
    std::optional<double> ended_at;
    std::optional<Fix> latest;  // the fix with the largest t
    std::size_t fixes = 0;
    FusionMethod fusion = FusionMethod::walk_pf;  // tracks/fusion_method.hpp
    FusionOptions fusion_options;                 // the Kalman methods' noise (tracks/fusion_options.hpp)
};

struct Opened {
    TrackInfo info;
    std::string token;
};

struct Posted {
    std::size_t stored = 0, duplicates = 0;
    std::optional<Fix> latest;
};

struct Share {
    std::int64_t id = 0, track_id = 0;
    std::string token;
};

// What an event stream is to write next: new fixes (in the order they were stored), or only a
// heartbeat; `ended` once the track closed or went, or the server is stopping.
struct Events {
    std::vector<Fix> fixes;
    bool ended = false;
    bool evicted = false;  // ended by the server to let another client's stream in (event_streams.hpp)
};

// What a map's positions stream is to write next (a stream may follow one floor):
// `position`: a track's new latest fix on the followed floor(s); `leave`: a track shown before
// left them, to `fix`'s floor, or ended (no fix). `ended` once the server is stopping.
struct MapEvent {
    enum class Kind { position, leave };
    Kind kind = Kind::position;
    std::int64_t track_id = 0;
    std::string label;
    std::optional<Fix> fix;
};
struct MapEvents {
    std::vector<MapEvent> events;
    bool ended = false;
    bool evicted = false;  // as Events::evicted
};

}  // namespace locus::tracks
