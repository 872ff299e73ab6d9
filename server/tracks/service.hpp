#pragma once
// Live tracks (docs/tracks.md): who is where now, for the owner of a track and those it shares with.
//
// A track's fixes are rows of the database (schema/008_tracks.sql), written on the service's
// own SQLite connection to the store's file: a thousand phones posting a fix a second would
// otherwise queue behind every CRUD and scan write on the store's one lock. What readers ask
// for often (each track's state, latest fix, token hashes, the last fixes for event streams)
// is also kept in memory. A sweeper thread closes a track after `ttl_s` without a fix and
// purges it `retention_s` after it closed: the privacy model (README "Live tracks").
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "locus/motion/fusion/walkable.hpp"
#include "store/db.hpp"
#include "store/store.hpp"
#include "tracks/fix.hpp"
#include "tracks/fusion_method.hpp"
#include "tracks/fusion_options.hpp"

namespace locus::tracks {

enum class State { live, closed, gone };
const char* state_name(State s);

struct Options {
    double ttl_s = 600;            // a live track with no fix for this long closes
    double retention_s = 86'400;   // a closed track's fixes and shares are deleted this long after it closed
    double heartbeat_s = 15;       // an event stream writes a comment this often when nothing happens
    std::size_t max_streams = 100;      // open event streams, all tracks together
    std::size_t max_streams_per_track = 10;  // so one owner (or its shares) cannot take every slot
    std::size_t max_live_tracks = 10'000;
    // What one client (one address, http/front/client_address.hpp) may hold of the two caps above,
    // so it cannot fill them for everyone (docs/deploy.md "Per-client limits"). Live tracks
    // are counted in the database (its keyed hash, schema/015_track_client.sql: across
    // replicas and restarts that share `client_key`); streams by this process.
    std::size_t max_live_tracks_per_client = 100;
    std::size_t max_streams_per_client = 10;
    // The key of the clients' hashes: derived from the API key, so replicas share it and the
    // database alone does not give it; empty: a random key for this process.
    std::string client_key;
    // Tracks held at all: live, closed within the retention period, and the tombstones of
    // deleted or expired ones (kept one more retention period). Bounds what a loop of
    // anonymous open/close (or open/delete) can make the server hold. Only live tracks fill
    // it: at the cap, opening a track evicts the oldest tombstone, else the closed track that
    // closed first, so such a loop cannot lock everyone else out of opening tracks.
    std::size_t max_tracks = 50'000;
    std::size_t max_fixes_per_track = 200'000;  // more than two days at one fix a second
    std::size_t event_buffer = 64;  // fixes kept per track for a stream that falls behind (streams wake at each fix)
    std::size_t map_event_buffer = 4096;  // map-level changes kept for positions streams, all maps together
};

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
};

class ThinFusion;
struct RadioFix;
struct FloorAnchors;

class Service {
    struct Track;

public:
    Service(store::Store& store, Options options);
    ~Service();
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    const Options& options() const { return options_; }
    // Wakes every event stream to end and stops the sweeper; called before the HTTP server stops.
    void stop();

    // A new live track on an existing map (store::NotFound otherwise).
    // `options` must be validated against kFusionOptions for `fusion`. `client`: who opens it,
    // counted against max_live_tracks_per_client (Refused(client_live_tracks)) after the
    // server-wide cap; none: exempt (the operator's API key).
    Opened open(std::int64_t map_id, const std::string& label, FusionMethod fusion = FusionMethod::walk_pf,
                const FusionOptions& options = {}, const std::optional<std::string>& client = std::nullopt);
    // What `token` may do with track `id`. An unknown track and a wrong token are refused alike
    // (forbidden), so a token says nothing about tracks it does not open; the owner of a track
    // that went is told so (gone). On PostgreSQL the track is first read again from the
    // database, so a phone's requests may alternate between servers sharing it.
    Access authorize(std::int64_t id, const std::string& token);

    // Fixes must be validated (finite, in range); the first floor not on the track's map is
    // returned (nothing stored), else nullopt after storing them in one transaction. A t
    // already stored is a duplicate and keeps the first fix.
    std::optional<std::int64_t> misplaced_floor(std::int64_t id, const std::vector<Fix>& fixes);
    Posted post(std::int64_t id, const std::vector<Fix>& fixes);
    // A thin client's raw steps and radio fixes, fused by client-lib's filter the track chose
    // (tracks/fusion.hpp), seeded with the track's id, and stored as the track's fixes; answers them with the post's counts.
    // std::invalid_argument when the filter cannot run (steps before any fix; no plan for particle).
    // `anchors`: ekf_ranging's, the map's known transmitters (tracks/fusion.hpp), else unused.
    std::pair<Posted, std::vector<Fix>> post_raw(std::int64_t id, const std::vector<Step>& steps, const std::vector<RadioFix>& radio,
                                                 std::shared_ptr<const FloorAnchors> anchors = nullptr);
    // Returns the track as closed, taken under the lock: an open at --max-tracks may evict a
    // closed track the moment after, so looking it up again could find it gone.
    TrackInfo close(std::int64_t id);
    void remove(std::int64_t id);

    TrackInfo info(std::int64_t id) const;
    // The `limit` latest fixes, oldest first.
    std::vector<Fix> trail(std::int64_t id, std::size_t limit);
    std::vector<TrackInfo> live_on_map(std::int64_t map_id, std::optional<std::int64_t> floor_id) const;

    Share add_share(std::int64_t id);
    void revoke_share(std::int64_t id, std::int64_t share_id);  // store::NotFound for a share not of this track

    class Stream {
    public:
        ~Stream();

    private:
        friend class Service;
        Stream(Service& s, std::shared_ptr<Track> t) : service_(s), track_(std::move(t)) {}
        Service& service_;
        std::shared_ptr<Track> track_;
        std::optional<std::string> share_hash_;  // read with a share: the stream ends when it is revoked
        std::optional<std::string> client_;      // counted in client_streams_
        std::uint64_t seen_ = 0;
        bool started_ = false;
    };
    // Refused(busy) past max_streams, then Refused(client_streams) past the client's
    // max_streams_per_client (track and map streams together; no client: exempt).
    // The token is authorised as by authorize(); a stream opened with a share ends when the share is revoked.
    std::unique_ptr<Stream> open_stream(std::int64_t id, const std::string& token, const std::optional<std::string>& client = std::nullopt);
    // The first call answers the latest fix; each later one waits up to heartbeat_s for more.
    Events next_events(Stream& stream);

    // Every live track of a map (or of one of its floors), then their changes: the viewer's live
    // layer. Shares max_streams with the track streams: Refused(busy) past it.
    class MapStream {
    public:
        ~MapStream();

    private:
        friend class Service;
        MapStream(Service& s, std::int64_t map_id, std::optional<std::int64_t> floor_id) : service_(s), map_id_(map_id), floor_id_(floor_id) {}
        Service& service_;
        std::int64_t map_id_;
        std::optional<std::int64_t> floor_id_;
        std::unordered_set<std::int64_t> shown_;  // tracks whose last position this stream wrote
        std::optional<std::string> client_;       // counted in client_streams_
        std::uint64_t seen_ = 0;
        bool started_ = false;
    };
    std::unique_ptr<MapStream> open_map_stream(std::int64_t map_id, std::optional<std::int64_t> floor_id,
                                               const std::optional<std::string>& client = std::nullopt);
    // The first call answers every live track's latest fix; each later one waits up to heartbeat_s for changes.
    MapEvents next_map_events(MapStream& stream);

    // One sweep now (the sweeper thread's work; tests call it through tiny flags instead).
    void sweep();
    static double now();

private:
    std::vector<std::int64_t> sweep_tracks();  // closes and purges; answers the tracks no longer live
    // Under mu_: a track's new latest fix (or its end, no fix) for the map streams.
    void publish(const TrackInfo& track, std::optional<Fix> fix);
    // Under mu_: the track went (deleted, expired, its map deleted) at `t`; only its tombstone stays.
    void mark_gone(Track& track, double t);
    // Under mu_: the `n` tracks opening a track at max_tracks drops, tombstones before closed
    // tracks, each oldest first; fewer when the rest are live.
    std::vector<std::shared_ptr<Track>> evictable(std::size_t n) const;
    // A map was deleted: the database dropped its tracks with it (ON DELETE CASCADE); in
    // memory they go too, so their owners are told 404 and their streams end.
    void map_deleted(std::int64_t map_id);
    std::shared_ptr<Track> find(std::int64_t id) const;  // under mu_; Refused(forbidden) for no such track
    // Under db_mu_: open()'s writes, in one transaction: the evicted tracks go, the new one is stored.
    // `client_hash`: the opener's keyed hash, counted against max_live_tracks_per_client in the
    // same transaction (Refused(client_live_tracks), nothing written); empty: exempt.
    TrackInfo insert_track(std::int64_t map_id, const std::string& label, FusionMethod fusion, const FusionOptions& options,
                           const std::string& hash, double t, const std::vector<std::shared_ptr<Track>>& evicted,
                           const std::string& client_hash);
    void load();
    // PostgreSQL, several servers: the track as the database holds it now (another server may
    // have opened it, stored its fixes, shared or closed it); its streams and its map's streams
    // are told what changed as if it had happened here. Takes db_mu_, then mu_.
    void refresh(std::int64_t id);
    void sweeper();
    // PostgreSQL: inside a write transaction on db_, tells the other
    // servers that these tracks (id, map id) changed (store::announce_tracks); nothing on SQLite.
    void announce(const std::vector<std::pair<std::int64_t, std::int64_t>>& tracks);
    // Another server's change (the feed, on the watcher thread): whether this server's streams
    // care, then refreshing on refresher_'s thread, so the watcher never waits for db_mu_.
    void on_track_change(std::int64_t id, std::optional<std::int64_t> map_id);
    // Under mu_: `id` read again on refresher_'s thread (each id once while queued); nothing on one server.
    void queue_refresh(std::int64_t id);
    // Every track a stream here follows, and every live track of a map a positions stream here
    // follows, read again: after "everything changed" (a missed notification, a reconnect).
    void catch_up();
    void catch_up_map(std::int64_t map_id);  // the live tracks of one map
    void refresher();
    bool stopping() const;  // takes mu_

    store::Store& store_;
    Options options_;
    mutable std::mutex db_mu_;  // the connection; taken before mu_ when both are held
    store::Db db_;
    mutable std::mutex mu_;
    std::unordered_map<std::int64_t, std::shared_ptr<Track>> tracks_;
    std::unordered_map<std::int64_t, std::unordered_set<std::int64_t>> floors_of_map_;  // floors seen on each map
    std::size_t streams_ = 0;
    // Under mu_: streams open per client; a client with none has no entry, so this holds at
    // most max_streams entries.
    std::unordered_map<std::string, std::size_t> client_streams_;
    // Under mu_: one more stream for `client` (none: exempt), Refused(client_streams) at its cap.
    void count_client_stream(const std::optional<std::string>& client);
    void uncount_client_stream(const std::optional<std::string>& client);
    struct MapChange {
        std::uint64_t seq;
        std::int64_t map_id, track_id;
        std::string label;
        std::optional<Fix> fix;  // none: the track ended
    };
    std::deque<MapChange> map_changes_;  // the latest map_event_buffer, all maps
    std::uint64_t map_seq_ = 0;
    std::condition_variable map_changed_;  // waited on with mu_
    std::mutex fusion_mu_;  // the two below; taken before db_mu_
    std::unordered_map<std::int64_t, std::shared_ptr<ThinFusion>> fusions_;
    std::unordered_map<std::int64_t, std::shared_ptr<const fusion::Walkable>> walkables_;  // by floor; dropped when its plan changes
    std::size_t subscription_ = 0;
    bool stopping_ = false;
    std::condition_variable sweep_cv_;
    std::thread sweeper_;
    std::string origin_;  // this server in change announcements; empty: no other server to tell
    std::unordered_map<std::int64_t, std::size_t> map_streams_;  // positions streams open, by map
    // Under mu_: other servers' track changes waiting for refresher_, each track once.
    std::deque<std::int64_t> to_refresh_;
    std::unordered_set<std::int64_t> queued_;
    bool catch_up_ = false;
    std::unordered_set<std::int64_t> maps_to_catch_up_;  // new positions streams' maps
    std::condition_variable refresh_cv_;
    std::thread refresher_;
};

}  // namespace locus::tracks
