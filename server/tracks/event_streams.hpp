#pragma once
// The event streams of live tracks (docs/tracks.md): a track's stream (its new fixes) and a
// map's positions stream (the viewer's live layer: every live track's latest fix, then its
// changes), their counts against --max-track-streams, --max-streams-per-track and each
// client's --client-streams, and the one bounded log of map-level changes positions streams
// read (publish). A stream waits on a condition variable with the cache's mutex
// (tracks/track_cache.hpp): a track's own for its fixes, this log's for map changes; a wake is
// O(waiting streams), a read of the log O(map_event_buffer).
//
// The server-wide cap stays fair: when it is full, a new stream is let in by ending the oldest
// stream of the client that holds the most, if that client holds at least two more than the
// newcomer (an operator's stream, with the key, counts as a client holding none, and is never
// ended so). However many addresses fill the cap, a phone holding fewer streams than they do
// still opens its own; the evicted stream ends with `evicted` set. Choosing the victim is
// O(clients holding streams), at most max_streams.
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "tracks/options.hpp"
#include "tracks/track_cache.hpp"
#include "tracks/track_info.hpp"

namespace locus::tracks {

// A stream's place in the count: what it holds (a track's slot, or its map's) and, for a
// client's stream, its turn among that client's streams; `evicted` once the server ended it to
// let another client's stream in (its slots are given back then, not at close).
struct StreamTicket {
    std::optional<std::string> client;
    std::uint64_t order = 0;  // opening order: a client's oldest goes first
    std::shared_ptr<CachedTrack> track;  // a track stream's track
    std::optional<std::int64_t> map_id;  // a positions stream's map
    std::condition_variable* wakes = nullptr;  // what its next() waits on
    bool evicted = false;
};

// Where one track stream is: what it read last.
struct TrackStreamState {
    std::shared_ptr<StreamTicket> ticket;
    std::shared_ptr<CachedTrack> track;
    std::optional<std::string> share_hash;  // read with a share: the stream ends when it is revoked
    std::optional<std::string> client;      // counted against max_streams_per_client
    std::uint64_t seen = 0;
    bool started = false;
};

// Where one positions stream is: its map (and floor) and the tracks it shows.
struct MapStreamState {
    std::shared_ptr<StreamTicket> ticket;
    std::int64_t map_id = 0;
    std::optional<std::int64_t> floor_id;
    std::unordered_set<std::int64_t> shown;  // tracks whose last position this stream wrote
    std::optional<std::string> client;       // counted against max_streams_per_client
    std::uint64_t seen = 0;
    bool started = false;
};

class EventStreams {
public:
    EventStreams(TrackCache& cache, const Options& options) : cache_(cache), options_(options) {}

    // Under the cache's mutex:
    // A track's new latest fix (or its end, no fix) for the positions streams. O(1).
    void publish(const TrackInfo& track, std::optional<Fix> fix);
    // The track went (deleted, expired, its map deleted) at `t`; only its tombstone stays.
    void mark_gone(CachedTrack& track, double t);
    // Whether a positions stream here follows the map; every map one follows.
    bool map_watched(std::int64_t map_id) const;
    std::vector<std::int64_t> watched_maps() const;
    void wake();  // the service stops: positions streams end
    // A new track stream on `track`: Refused(busy) past max_streams when no client holds enough
    // more to give one up, Refused(too_many_streams) past max_streams_per_track, then
    // Refused(client_streams) past the client's share.
    TrackStreamState open(std::shared_ptr<CachedTrack> track, std::int64_t id, const std::optional<std::string>& client);
    // A new positions stream: Refused(busy), then Refused(client_streams), as above.
    MapStreamState open_map(std::int64_t map_id, std::optional<std::int64_t> floor_id, const std::optional<std::string>& client);

    // Taking the cache's mutex:
    void close(TrackStreamState& s);
    void close(MapStreamState& s);
    // The first call answers the latest fix; each later one waits up to wait_s for more.
    Events next(TrackStreamState& s, double wait_s);
    // The first call answers every live track's latest fix; each later one waits up to wait_s for changes.
    MapEvents next(MapStreamState& s, double wait_s);

private:
    std::size_t held_by(const std::optional<std::string>& client) const;
    // The oldest stream of the client holding the most, when the server is full and that client
    // holds at least two more than `client`; null when there is room, Refused(busy) when there
    // is neither room nor such a stream.
    std::shared_ptr<StreamTicket> room_for(const std::optional<std::string>& client) const;
    // Refused(client_streams) at the client's cap (none: exempt).
    void check_client(const std::optional<std::string>& client) const;
    // Counts the stream (after the evictee, if any, gives its slots back) and files it.
    std::shared_ptr<StreamTicket> admit(StreamTicket ticket, const std::shared_ptr<StreamTicket>& evictee);
    void release(StreamTicket& ticket);  // gives back what it counted

    TrackCache& cache_;
    const Options& options_;
    std::size_t streams_ = 0;
    // Streams open per client, by opening order; a client with none has no entry, so this holds
    // at most max_streams entries.
    std::unordered_map<std::string, std::map<std::uint64_t, std::shared_ptr<StreamTicket>>> client_streams_;
    std::uint64_t opened_ = 0;
    std::unordered_map<std::int64_t, std::size_t> map_streams_;  // positions streams open, by map
    struct MapChange {
        std::uint64_t seq;
        std::int64_t map_id, track_id;
        std::string label;
        std::optional<Fix> fix;  // none: the track ended
    };
    std::deque<MapChange> map_changes_;  // the latest map_event_buffer, all maps
    std::uint64_t map_seq_ = 0;
    std::condition_variable map_changed_;  // waited on with the cache's mutex
};

}  // namespace locus::tracks
