#pragma once
// Live tracks (docs/tracks.md): who is where now, for the owner of a track and those it shares with.
//
// A track's fixes are rows of the database (schema/008_tracks.sql), written on the service's
// own connection to the store's file (store/track_repository.hpp, which holds every statement):
// a thousand phones posting a fix a second would otherwise queue behind every CRUD and scan
// write on the store's one lock. What readers ask for often (each track's state, latest fix,
// token hashes, the last fixes for event streams) is also kept in memory (tracks/track_cache.hpp).
// A sweeper thread closes a track after `ttl_s` without a fix and purges it `retention_s` after
// it closed: the privacy model (README "Live tracks"; tracks/sweeper.hpp). Event streams and
// their limits are tracks/event_streams.hpp's; on PostgreSQL shared by several servers, other
// servers' changes are read again by tracks/replication.hpp. This class is their facade: it
// checks a request against the cache, writes through the repository, then updates the cache
// and wakes the streams. Locks, when more are held, in this order: the thin clients' filters
// (tracks/fusion_sessions.hpp), the repository's, the cache's.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "locus/motion/fusion/walkable.hpp"
#include "store/store.hpp"
#include "store/track_repository.hpp"
#include "tracks/event_streams.hpp"
#include "tracks/fix.hpp"
#include "tracks/fusion_method.hpp"
#include "tracks/fusion_options.hpp"
#include "tracks/fusion_sessions.hpp"
#include "tracks/options.hpp"
#include "tracks/replication.hpp"
#include "tracks/sweeper.hpp"
#include "tracks/track_cache.hpp"
#include "tracks/track_info.hpp"

namespace locus::tracks {

struct RadioFix;
struct FloorAnchors;

class Service {
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
    // A thin client's raw steps, radio fixes, pressure samples and GNSS fixes, fused by
    // client-lib's filter the track chose (tracks/fusion.hpp), seeded with the track's id, and
    // stored as the track's fixes; answers them with the post's counts. std::invalid_argument
    // when the filter cannot run (steps before any fix; no plan for particle). `anchors`:
    // ekf_ranging's, the map's known transmitters (tracks/fusion.hpp), else unused. `sources`:
    // the floors' georeferences and walk_pf's scans (tracks/run_sources.hpp), asked during the
    // run with the track's run lock held; whatever it throws passes through, nothing written.
    std::pair<Posted, std::vector<Fix>> post_raw(std::int64_t id, const std::vector<Step>& steps, const std::vector<RadioFix>& radio,
                                                 const std::vector<Pressure>& pressure = {}, const std::vector<Gnss>& gnss = {},
                                                 std::shared_ptr<const FloorAnchors> anchors = nullptr, RunSources* sources = nullptr);
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
        Stream(EventStreams& s, TrackStreamState state) : streams_(s), state_(std::move(state)) {}
        EventStreams& streams_;
        TrackStreamState state_;
    };
    // Refused(busy) past max_streams, then Refused(client_streams) past the client's
    // max_streams_per_client (track and map streams together; no client: exempt).
    // The token is authorised as by authorize(); a stream opened with a share ends when the share is revoked.
    std::unique_ptr<Stream> open_stream(std::int64_t id, const std::string& token, const std::optional<std::string>& client = std::nullopt);
    // The first call answers the latest fix; each later one waits up to wait_s for more (the
    // route waits a heartbeat_s in short slices, checking its reader between them).
    Events next_events(Stream& stream, double wait_s);

    // Every live track of a map (or of one of its floors), then their changes: the viewer's live
    // layer. Shares max_streams with the track streams: Refused(busy) past it.
    class MapStream {
    public:
        ~MapStream();

    private:
        friend class Service;
        MapStream(EventStreams& s, MapStreamState state) : streams_(s), state_(std::move(state)) {}
        EventStreams& streams_;
        MapStreamState state_;
    };
    std::unique_ptr<MapStream> open_map_stream(std::int64_t map_id, std::optional<std::int64_t> floor_id,
                                               const std::optional<std::string>& client = std::nullopt);
    // The first call answers every live track's latest fix; each later one waits up to wait_s for changes.
    MapEvents next_map_events(MapStream& stream, double wait_s);

    // One sweep now (the sweeper thread's work; tests call it through tiny flags instead).
    void sweep();
    static double now();

private:
    // A map was deleted: the database dropped its tracks with it (ON DELETE CASCADE); in
    // memory they go too, so their owners are told 404 and their streams end.
    void map_deleted(std::int64_t map_id);
    // Under the repository's mutex: open()'s writes, in one transaction: the evicted tracks go,
    // the new one is stored. `client_hash`: the opener's keyed hash, counted against
    // max_live_tracks_per_client in the same transaction (Refused(client_live_tracks), nothing
    // written); empty: exempt.
    TrackInfo insert_track(std::int64_t map_id, const std::string& label, FusionMethod fusion, const FusionOptions& options,
                           const std::string& hash, double t, const std::vector<std::shared_ptr<CachedTrack>>& evicted,
                           const std::string& client_hash);
    void on_change(const store::Change& c);  // the store's feed

    store::Store& store_;
    Options options_;
    store::TrackRepository repo_;
    TrackCache cache_;
    EventStreams streams_{cache_, options_};
    Replication replication_{repo_, cache_, streams_, options_};
    Sweeper sweeper_{repo_, cache_, streams_, replication_, options_};
    FusionSessions fusions_{store_};  // the thin clients' filters; their lock before the repository's
    std::size_t subscription_ = 0;
};

}  // namespace locus::tracks
