#pragma once
// Localization over in-memory indexes (locus::match) of every radio map and every map.
// Indexes are built from the store at start and rebuilt after writes by a background thread
// that paces itself. A query on a small index a write made stale rebuilds it first (its answer
// reflects every committed write); one on a big index gets the previous snapshot while the
// background catches up (see Options). Queries run on an immutable index with no lock held
// and never touch SQLite.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/match/index.hpp"
#include "locus/match/tune.hpp"
#include "store/store.hpp"

namespace locus::localize {

// An index with the rooms of the floors it covers (for the symbolic location), and each RP's
// part of a candidate in the JSON answer, written once per snapshot by the answer writer
// (http/localize/localize_answer.hpp) through the Prepare hook; this layer only keeps the text.
struct Snapshot {
    match::Index index;
    std::unordered_map<long long, std::vector<Room>> rooms_by_floor;
    struct CandidateJson {
        std::string head;  // {"rp_id":..,"x":..,"y":..,"score":
        std::string tail;  // ,"floor_id":..,"building_id":..,"matched_aps":
    };
    std::unordered_map<long long, CandidateJson> candidate_json;  // by RP id
    // The radio map's stored settings as the store keeps them (JSON text; empty: none). A
    // map's index takes its radio maps' settings when all of them (those holding RPs) store
    // the same, else none: one building's tuned choice is no reason for another's.
    std::string settings_text;
    // What a request that does not specify gets: the Prepare hook reads it from settings_text.
    match::Setting defaults;
};

// How stale an index may get, and how much of a core keeping it fresh may take. The
// reasoning is at Service::lookup and Service::refresher; tests shorten or
// stretch them. (Outside Service: a nested class with default member initializers cannot be a
// default argument of its enclosing class's constructor.)
struct ServiceOptions {
    using Duration = std::chrono::steady_clock::duration;
    // A stale index of at most this many RPs is rebuilt on the query's thread. A count, not a
    // build time: a timed limit would flip under load or sanitizers and lose read-your-writes.
    std::size_t sync_rebuild_max_rps = 2000;
    // Writes settle this long before the background rebuilds, so a burst costs one rebuild.
    Duration settle = std::chrono::milliseconds(50);
    // A round of background rebuilds starts no sooner than pace_factor times the last
    // round's duration after it: continuous writes take at most 1 / (1 + pace_factor) of a core.
    double pace_factor = 3.0;
};

class Service {
public:
    enum class Scope { radiomap, map };
    // Called on each new snapshot before it is published, to add what answers need.
    using Prepare = std::function<void(Snapshot&)>;
    using Duration = std::chrono::steady_clock::duration;
    using Options = ServiceOptions;

    // Builds every radio map's and map's index, and subscribes to the store's change feed:
    // construct it before the server serves.
    Service(store::Store& store, Prepare prepare = {}, Options options = {});
    ~Service();
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // The snapshot of a radio map's or a map's index: rebuilt first if a committed write made
    // it stale and it is small, else the last one built (see Options); throws store::NotFound
    // for an unknown id.
    std::shared_ptr<const Snapshot> lookup(Scope scope, std::int64_t id);
    // Background rebuilds so far (all scopes), for tests and benches.
    std::size_t background_rebuilds() const;

private:
    using Clock = std::chrono::steady_clock;
    // One index: stale while built < wanted. A write bumps wanted; a build takes the wanted it
    // saw before reading the store and publishes only if that is newer than what is published,
    // so concurrent builds (query threads, the background) never publish an older one last.
    struct Entry {
        std::shared_ptr<const Snapshot> snapshot;
        std::uint64_t wanted = 1, built = 0;
        // A query rebuilds (however big) until built reaches this: set by deletes, so a deleted
        // radio map is not found and a deleted floor's RPs are gone at once, as before.
        std::uint64_t sync_before = 0;
        bool stale() const { return built < wanted; }
    };
    using Table = std::unordered_map<std::int64_t, Entry>;
    Table& table(Scope scope) { return scope == Scope::radiomap ? radiomaps_ : maps_; }
    // The snapshot a query may be answered from without rebuilding, else null.
    std::shared_ptr<const Snapshot> servable(Scope scope, std::int64_t id);
    // The newest snapshot after building one; throws store::NotFound for an unknown id.
    std::shared_ptr<const Snapshot> rebuild(Scope scope, std::int64_t id);
    // The settings every radio map of these RPs stores alike, else empty.
    std::string common_settings(const std::vector<store::StoredRp>& stored);
    void mark_dirty(Scope scope, std::int64_t id, bool sync = false);
    // An index (every index) is stale; with `sync`, queries rebuild it whatever its size.
    void mark_all_dirty(bool sync = false);
    void refresher();
    // Marks what a committed write touched as stale.
    void on_change(const store::Change& change);

    store::Store& store_;
    Prepare prepare_;
    Options options_;
    std::size_t subscription_ = 0;
    mutable std::mutex mu_;  // guards the tables below, never held while building
    Table radiomaps_, maps_;
    std::size_t background_rebuilds_ = 0;
    std::mutex query_build_mu_;  // one query-thread rebuild at a time (see lookup)
    std::condition_variable wake_;
    bool stopping_ = false;
    std::thread worker_;
};

}  // namespace locus::localize
