#pragma once
// Localization over in-memory indexes (locus::match) of every radio map and every map.
// Indexes are built from the store at start and rebuilt after writes: a background thread
// rebuilds what a write touched, and a query that arrives before it has done so rebuilds
// its own index first, so an answer always reflects every committed write. Queries then
// run on an immutable index with no lock held and never touch SQLite.
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/match/index.hpp"
#include "store/repository.hpp"

namespace locus::http {
class App;
}

namespace locus::localize {

// An index with the rooms of the floors it covers (for the symbolic location), and each RP's
// part of a candidate in the JSON answer, written once per snapshot (request.hpp).
struct Snapshot {
    match::Index index;
    std::unordered_map<long long, std::vector<Room>> rooms_by_floor;
    struct CandidateJson {
        std::string head;  // {"rp_id":..,"x":..,"y":..,"score":
        std::string tail;  // ,"floor_id":..,"building_id":..,"matched_aps":
    };
    std::unordered_map<long long, CandidateJson> candidate_json;  // by RP id
};

class Service {
public:
    explicit Service(store::Repository& repo);
    ~Service();
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // Adds POST /v1/radiomaps/{id}/localize and POST /v1/maps/{id}/localize, and follows writes.
    void install(http::App& app);


    // Marks what a write touched as stale (called by the HTTP layer after each commit).
    void on_write(std::string_view kind, const nlohmann::json& row, bool deleted);

private:
    enum class Scope { radiomap, map };
    using Table = std::unordered_map<std::int64_t, std::shared_ptr<const Snapshot>>;
    Table& table(Scope scope) { return scope == Scope::radiomap ? radiomaps_ : maps_; }
    std::unordered_set<std::int64_t>& dirty(Scope scope) { return scope == Scope::radiomap ? dirty_radiomaps_ : dirty_maps_; }
    // The current snapshot; throws store::NotFound for an unknown id.
    std::shared_ptr<const Snapshot> lookup(Scope scope, std::int64_t id);
    std::shared_ptr<const Snapshot> rebuild(Scope scope, std::int64_t id);
    void mark_dirty(Scope scope, std::int64_t id);
    void mark_all_dirty();
    void refresher();

    store::Repository& repo_;
    std::mutex mu_;  // guards the tables below, never held while building
    Table radiomaps_, maps_;
    std::unordered_set<std::int64_t> dirty_radiomaps_, dirty_maps_;
    std::condition_variable wake_;
    bool stopping_ = false;
    std::mutex build_mu_;  // one rebuild at a time, so the newest snapshot is published last
    std::thread worker_;
};

}  // namespace locus::localize
