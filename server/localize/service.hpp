#pragma once
// Localization over in-memory indexes (locus::match) of every radio map and every map.
// Indexes are built from the store at start and rebuilt after writes: a background thread
// rebuilds what a write touched, and a query that arrives before it has done so rebuilds
// its own index first, so an answer always reflects every committed write. Queries then
// run on an immutable index with no lock held and never touch SQLite.
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
// (http/localize_answer.hpp) through the Prepare hook; this layer only keeps the text.
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

class Service {
public:
    enum class Scope { radiomap, map };
    // Called on each new snapshot before it is published, to add what answers need.
    using Prepare = std::function<void(Snapshot&)>;

    // Builds every radio map's and map's index, and subscribes to the store's change feed:
    // construct it before the server serves.
    Service(store::Store& store, Prepare prepare = {});
    ~Service();
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // The current snapshot of a radio map's or a map's index, rebuilt first if a committed
    // write made it stale; throws store::NotFound for an unknown id.
    std::shared_ptr<const Snapshot> lookup(Scope scope, std::int64_t id);

private:
    using Table = std::unordered_map<std::int64_t, std::shared_ptr<const Snapshot>>;
    Table& table(Scope scope) { return scope == Scope::radiomap ? radiomaps_ : maps_; }
    std::unordered_set<std::int64_t>& dirty(Scope scope) { return scope == Scope::radiomap ? dirty_radiomaps_ : dirty_maps_; }
    // The current snapshot; throws store::NotFound for an unknown id.
    std::shared_ptr<const Snapshot> rebuild(Scope scope, std::int64_t id);
    // The settings every radio map of these RPs stores alike, else empty.
    std::string common_settings(const std::vector<store::StoredRp>& stored);
    void mark_dirty(Scope scope, std::int64_t id);
    void mark_all_dirty();
    void refresher();
    // Marks what a committed write touched as stale.
    void on_change(const store::Change& change);

    store::Store& store_;
    Prepare prepare_;
    std::size_t subscription_ = 0;
    std::mutex mu_;  // guards the tables below, never held while building
    Table radiomaps_, maps_;
    std::unordered_set<std::int64_t> dirty_radiomaps_, dirty_maps_;
    std::condition_variable wake_;
    bool stopping_ = false;
    std::mutex build_mu_;  // one rebuild at a time, so the newest snapshot is published last
    std::thread worker_;
};

}  // namespace locus::localize
