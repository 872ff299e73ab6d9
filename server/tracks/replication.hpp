#pragma once
// Several servers sharing one PostgreSQL database (docs/deploy.md): a track another server
// opened, posted to, shared, closed or deleted is read again here, and this server's streams
// (tracks/event_streams.hpp) are told what changed as if it had happened here. The feed hands
// on other servers' track changes (store/pg_changes.hpp, on its watcher thread); only those a
// stream here cares about are queued, and a refresher thread of this object reads them, so the
// watcher never waits for the connection. A refresh is one snapshot of a few indexed reads (a
// round trip each); a catch-up ("everything changed": a missed notification, a reconnect)
// refreshes every track a stream here follows. On one server nothing is queued and no thread runs.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <unordered_set>
#include <vector>

#include "store/track_repository.hpp"
#include "tracks/event_streams.hpp"
#include "tracks/options.hpp"
#include "tracks/track_cache.hpp"

namespace locus::tracks {

class Replication {
public:
    Replication(store::TrackRepository& repo, TrackCache& cache, EventStreams& streams, const Options& options)
        : repo_(repo), cache_(cache), streams_(streams), options_(options) {}
    Replication(const Replication&) = delete;
    Replication& operator=(const Replication&) = delete;

    void start();  // the refresher thread, when other servers share the database
    void join();   // after the cache is stopping and wake()

    // The track as the database holds it now; its streams and its map's streams are told what
    // changed. Takes the repository's mutex, then the cache's.
    void refresh(std::int64_t id);
    // Another server's change (the feed, on the watcher thread): queued when a stream here
    // cares. Takes the cache's mutex.
    void on_track_change(std::int64_t id, std::optional<std::int64_t> map_id);

    // Under the cache's mutex:
    // `id` read again on the refresher's thread (each id once while queued); nothing on one server.
    void queue_refresh(std::int64_t id);
    // Every followed track read again (after "everything changed"); nothing on one server.
    void catch_up_later();
    // A new positions stream's map: its live tracks read again; nothing on one server.
    void catch_up_map_later(std::int64_t map_id);
    void wake();  // the service stops

private:
    // What refresh() read of a track still stored, in one snapshot.
    struct Read {
        TrackInfo row;
        std::string hash;
        std::vector<Fix> fresh;  // the fixes stored since the latest held here, oldest first
        std::optional<std::size_t> counted;
        std::map<std::int64_t, std::string> shares;
    };
    Read read(std::int64_t id, const store::TrackRow& stored);
    // Under the repository's mutex: the row went (its map deleted, or evicted elsewhere).
    void vanished(std::int64_t id);
    // Takes the cache's mutex: `r` into the cache, the streams woken.
    void apply(std::int64_t id, Read r);
    void catch_up();
    void catch_up_map(std::int64_t map_id);  // the live tracks of one map
    void run();

    store::TrackRepository& repo_;
    TrackCache& cache_;
    EventStreams& streams_;
    const Options& options_;
    // Under the cache's mutex: other servers' track changes waiting for the refresher, each track once.
    std::deque<std::int64_t> to_refresh_;
    std::unordered_set<std::int64_t> queued_;
    bool catch_up_ = false;
    std::unordered_set<std::int64_t> maps_to_catch_up_;  // new positions streams' maps
    std::condition_variable refresh_cv_;                 // waited on with the cache's mutex
    std::thread refresher_;
};

}  // namespace locus::tracks
