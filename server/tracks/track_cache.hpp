#pragma once
// The in-memory copy of every track this server holds (live, closed within the retention
// period, and the tombstones of deleted or expired ones): what readers ask for often (each
// track's state, latest fix, token hashes, the last fixes for event streams) without a
// database read. A hash map by id; a lookup is O(1), a walk over all (live_on_map, counting
// live tracks) O(tracks), at most --max-tracks.
//
// Its mutex() is the lock of all of the tracks' in-memory state: the cache's, the event
// streams' counts and map-change log (tracks/event_streams.hpp) and the replication queue
// (tracks/replication.hpp); it is taken after the repository's (store/track_repository.hpp)
// when both are held. Methods say "under mutex()" when their caller holds it.
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "store/track_repository.hpp"
#include "tracks/track_info.hpp"

namespace locus::tracks {

// One track as held in memory; its fields under the cache's mutex.
struct CachedTrack {
    TrackInfo info;
    std::string token_hash;
    std::map<std::int64_t, std::string> shares;  // share id -> token hash
    std::uint64_t seq = 0;                       // fixes stored so far, for streams
    std::deque<std::pair<std::uint64_t, Fix>> recent;
    std::condition_variable changed;  // waited on with the cache's mutex
    std::size_t streams = 0;          // event streams open on it

    // A fix newly stored: numbered for the streams, the last `buffer` kept.
    void remember(const Fix& f, std::size_t buffer);
    // It went at `t`: only its tombstone stays (state, token hash, end); its streams are woken.
    void go(double t);
};

class TrackCache {
public:
    std::mutex& mutex() const { return mu_; }

    // Every track the database holds (one read of each table); under the repository's mutex.
    void load(store::TrackRepository& repo);

    // Under mutex():
    std::shared_ptr<CachedTrack> find(std::int64_t id) const;    // Refused(forbidden) for no such track
    std::shared_ptr<CachedTrack> lookup(std::int64_t id) const;  // null for no such track
    std::shared_ptr<CachedTrack>& slot(std::int64_t id) { return tracks_[id]; }  // null when new
    void erase(std::int64_t id) { tracks_.erase(id); }
    std::size_t size() const { return tracks_.size(); }
    std::size_t live() const;  // O(tracks)
    const std::unordered_map<std::int64_t, std::shared_ptr<CachedTrack>>& all() const { return tracks_; }
    // The floors seen on a map, asked of the store once each; forgotten when the hierarchy changes.
    std::unordered_set<std::int64_t>& floors_of(std::int64_t map_id) { return floors_of_map_[map_id]; }
    void forget_floors() { floors_of_map_.clear(); }
    // Set once by stop(): every stream ends, the threads leave.
    bool stopping() const { return stopping_; }
    // Marks the service stopping and wakes every track stream.
    void stop();

    // Takes mutex(): the live tracks of a map (or one floor) with a fix, by id. O(tracks).
    std::vector<TrackInfo> live_on_map(std::int64_t map_id, std::optional<std::int64_t> floor_id) const;
    bool is_stopping() const;  // takes mutex()

private:
    mutable std::mutex mu_;
    std::unordered_map<std::int64_t, std::shared_ptr<CachedTrack>> tracks_;
    std::unordered_map<std::int64_t, std::unordered_set<std::int64_t>> floors_of_map_;  // floors seen on each map
    bool stopping_ = false;
};

// Refused(forbidden)'s message: the same for an unknown track and a wrong token.
std::string forbidden_message(std::int64_t id);

}  // namespace locus::tracks
