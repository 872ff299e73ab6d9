#pragma once
// The privacy model (README "Live tracks", docs/tracks.md): a live track closes `ttl_s` after
// its last fix, a closed one is purged (fixes and shares deleted, a tombstone left)
// `retention_s` after it closed, and a tombstone is forgotten one more retention period on;
// fixes older than the retention period go even from a track still live. A thread runs a sweep
// every quarter of the shorter period (0.05 to 5 s). A sweep walks every track held (O(tracks)
// in memory) and runs one write transaction: a statement per track it ends, plus one delete
// scanning track_fixes by t; on PostgreSQL also one read per track it would close, since
// another server may have stored its fixes. Also here: which tracks an open at --max-tracks evicts.
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include "store/track_repository.hpp"
#include "tracks/event_streams.hpp"
#include "tracks/options.hpp"
#include "tracks/replication.hpp"
#include "tracks/track_cache.hpp"

namespace locus::tracks {

class Sweeper {
public:
    Sweeper(store::TrackRepository& repo, TrackCache& cache, EventStreams& streams, Replication& replication, const Options& options)
        : repo_(repo), cache_(cache), streams_(streams), replication_(replication), options_(options) {}
    Sweeper(const Sweeper&) = delete;
    Sweeper& operator=(const Sweeper&) = delete;

    // The thread, calling `work` (a sweep) each period until the cache is stopping; a storage fault is
    // retried at the next period.
    void start(std::function<void()> work);
    void join();   // after the cache is stopping and wake()
    void wake();   // under the cache's mutex: the service stops

    // Closes and purges; answers the tracks no longer live. Takes the repository's mutex, then the cache's.
    std::vector<std::int64_t> sweep();
    // Under the cache's mutex: the `n` tracks opening a track at max_tracks drops, tombstones
    // before closed tracks, each oldest first; fewer when the rest are live. O(tracks).
    std::vector<std::shared_ptr<CachedTrack>> evictable(std::size_t n) const;

private:
    using Tracks = std::vector<std::shared_ptr<CachedTrack>>;
    // PostgreSQL, in the sweep's transaction: of `to_close`, those the database says are quiet
    // too; `ended_elsewhere` gets those no longer live there.
    Tracks still_quiet(const Tracks& to_close, double t, std::vector<std::int64_t>& ended_elsewhere);
    void run(const std::function<void()>& work);

    store::TrackRepository& repo_;
    TrackCache& cache_;
    EventStreams& streams_;
    Replication& replication_;
    const Options& options_;
    std::condition_variable sweep_cv_;  // waited on with the cache's mutex
    std::thread thread_;
};

}  // namespace locus::tracks
