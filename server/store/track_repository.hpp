#pragma once
// Live tracks' rows (schema/008_tracks.sql, 015_track_client.sql): every statement the tracks
// service (server/tracks/) runs, on a connection of its own to the store's database rather than
// the store's (tracks/service.hpp says why), and the announcement of its writes to the other
// servers sharing a PostgreSQL database (store/pg_changes.hpp, announce_tracks).
//
// Rows are plain values (the store includes no tracks/ header): a track's state and fusion
// method are their stored names, its fusion options their stored text; tracks/track_rows.hpp
// turns them into the service's types. The repository takes no lock itself: its caller holds
// mutex() around each use (one connection), and groups statements into one transaction with
// Write or Snapshot. Each statement is one round trip on PostgreSQL (one
// prepared statement on this connection) or one step on SQLite; the costs below say what a
// statement reads.
#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "store/db.hpp"

namespace locus::store {

struct TrackRow {
    std::int64_t id = 0;
    std::optional<std::int64_t> map_id;  // none once gone
    std::string label;                   // empty: none
    std::string token_hash;
    std::string state;  // live, closed or gone
    double created_at = 0, last_fix_at = 0;
    std::optional<double> ended_at;
    std::string fusion;                         // the method's stored name
    std::optional<std::string> fusion_options;  // none: the method's defaults
};

struct FixRow {
    double t = 0;
    std::int64_t floor_id = 0;
    double x = 0, y = 0, accuracy_m = 0;
    std::optional<double> heading_deg;
};

struct LatestFixRow {
    std::int64_t track_id = 0;
    FixRow fix;  // the track's fix with the largest t
    std::size_t fixes = 0;
};

struct ShareRow {
    std::int64_t id = 0, track_id = 0;
    std::string token_hash;
};

struct NewTrackRow {
    std::int64_t map_id = 0;
    std::string label;  // empty: none
    std::string token_hash;
    double t = 0;  // created at, and its first last_fix_at
    std::string fusion;
    std::string fusion_options;  // empty: none
    std::string client_hash;     // empty: none (exempt from the per-client count)
};

// One client's live tracks: how many, and the last fix of the quietest.
struct ClientTracks {
    std::size_t held = 0;
    double quietest_last_fix_at = 0;
};

class TrackRepository {
public:
    // `connection`: the store's database (Store::connection()); `origin`: this server in change
    // announcements (Store::change_origin()), empty when no other server shares it.
    TrackRepository(const std::string& connection, std::string origin);
    TrackRepository(const TrackRepository&) = delete;
    TrackRepository& operator=(const TrackRepository&) = delete;

    // The connection's lock, taken around every use; the tracks' in-memory lock is taken after it.
    std::mutex& mutex() { return mu_; }
    bool is_postgres() const { return db_.is_postgres(); }
    // Whether other servers share the database (writes are announced, theirs arrive on the feed).
    bool replicated() const { return !origin_.empty(); }

    // A write transaction (BEGIN IMMEDIATE on SQLite); rolled back unless committed.
    class Write {
    public:
        explicit Write(TrackRepository& r) : tx_(r.db_) {}
        void commit() { tx_.commit(); }

    private:
        Transaction tx_;
    };
    // Reads from one snapshot (REPEATABLE READ on PostgreSQL).
    class Snapshot {
    public:
        explicit Snapshot(TrackRepository& r) : tx_(r.db_, Transaction::Mode::read) {}
        void commit() { tx_.commit(); }

    private:
        Transaction tx_;
    };

    // At startup, every row: each reads its whole table (the latest fixes with a window over track_fixes).
    std::vector<TrackRow> tracks();
    std::vector<LatestFixRow> latest_fixes();
    std::vector<ShareRow> shares();

    // One track's reads, by its primary key or the (track_id, t) index.
    std::optional<TrackRow> track(std::int64_t id);
    bool map_exists(std::int64_t map_id);
    std::optional<FixRow> latest_fix(std::int64_t id);
    // The `limit` latest fixes (after `after` when given), oldest first.
    std::vector<FixRow> last_fixes(std::int64_t id, std::optional<double> after, std::size_t limit);
    std::size_t fix_count(std::int64_t id);  // reads every fix of the track
    std::map<std::int64_t, std::string> shares_of(std::int64_t id);  // share id -> token hash
    std::vector<std::int64_t> live_on_map(std::int64_t map_id);
    // A track's last_fix_at while the database holds it live; none once it is not.
    std::optional<double> live_last_fix_at(std::int64_t id);

    // Writes, inside a Write.
    // The live tracks of a client with a fix since `since`. On PostgreSQL it first takes an
    // advisory lock for the rest of the transaction, so replicas count one open at a time.
    ClientTracks client_tracks(const std::string& client_hash, double since);
    std::int64_t insert(const NewTrackRow& row);
    // INSERT OR IGNORE each fix (a t already stored keeps the first); answers the indexes of
    // those stored. One statement per fix, prepared once.
    std::vector<std::size_t> insert_fixes(std::int64_t id, const std::vector<FixRow>& fixes);
    void touch(std::int64_t id, double t);  // last_fix_at
    void close(std::int64_t id, double t);  // closed at t; no longer counted for its client
    // Deleted at t: its fixes and shares go, only the tombstone row stays.
    void remove(std::int64_t id, double t);
    // Expired at t (the sweeper): as remove(), but the client hash, cleared at close, is left.
    void purge(std::int64_t id, double t);
    void forget(std::int64_t id);  // the tombstone row goes
    void drop(std::int64_t id);    // fixes, shares and row (an eviction)
    // Every fix older than `before` goes (a scan of track_fixes); whether any did.
    bool trim_fixes(double before);
    std::unordered_map<std::int64_t, std::size_t> fix_counts();  // per track, a scan of track_fixes
    std::int64_t add_share(std::int64_t id, const std::string& token_hash, double t);
    void remove_share(std::int64_t share_id);
    // PostgreSQL, other servers sharing it: tells them these tracks (id, map id) changed, in
    // the open write transaction (store::announce_tracks), fifty to a notification; nothing otherwise.
    void announce(const std::vector<std::pair<std::int64_t, std::int64_t>>& tracks);

private:
    std::mutex mu_;
    Db db_;
    std::string origin_;
};

}  // namespace locus::store
