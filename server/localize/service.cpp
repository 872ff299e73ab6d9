#include "localize/service.hpp"

#include <chrono>
#include <optional>
#include <string>

namespace locus::localize {

Service::Service(store::Store& store, Prepare prepare, Options options)
    : store_(store), prepare_(std::move(prepare)), options_(options) {
    subscription_ = store_.subscribe([this](const store::Change& change) { on_change(change); });
    try {
        std::unordered_set<std::int64_t> maps;
        for (const auto id : store_.radiomap_ids()) {
            rebuild(Scope::radiomap, id);
            maps.insert(store_.map_of_radiomap(id));
        }
        for (const auto id : maps) rebuild(Scope::map, id);
    } catch (...) {
        store_.unsubscribe(subscription_);  // no destructor will: the store must not call a dead service
        throw;
    }
    worker_ = std::thread([this] { refresher(); });
}

Service::~Service() {
    store_.unsubscribe(subscription_);
    {
        std::lock_guard lock(mu_);
        stopping_ = true;
    }
    wake_.notify_all();
    worker_.join();
}

// Stale-while-revalidate, for big indexes only. Rebuilding on the query's thread gives
// read-your-writes (a surveyor's upload shows in the next localize) and costs a few ms on a
// small radio map, so a query still does so when the index holds at most sync_rebuild_max_rps
// RPs. On a big map (100,000 RPs: seconds) every query during an upload stream
// would wait for a full rebuild, so it gets the previous snapshot instead and the background
// rebuilds. Staleness is then bounded by settle + (pace_factor + 2) x d, d the time of one
// background round (every stale index rebuilt once: a 100,000-RP radio map and its map take
// 1.8 s at 8 APs per RP, 7 s at 14.5, so 9 s to 35 s with the defaults; a surveyor's new
// data is not a fix anyone waits for, a localize stuck for seconds is): a write lands at
// worst just after a round began reading (d to wait it out), the next round is paced (the
// longer of settle and pace_factor x d) and takes d. Deletes are the exception (Entry::sync_before).
std::shared_ptr<const Snapshot> Service::lookup(Scope scope, std::int64_t id) {
    if (auto snap = servable(scope, id)) return snap;
    // Queries rebuild one at a time, each after checking that another has not just done so:
    // after a delete, concurrent queries on a big map must not build it once each (memory).
    // The background does not take this lock, so a query never waits behind its big builds.
    std::lock_guard build(query_build_mu_);
    if (auto snap = servable(scope, id)) return snap;
    return rebuild(scope, id);
}

std::shared_ptr<const Snapshot> Service::servable(Scope scope, std::int64_t id) {
    std::lock_guard lock(mu_);
    const auto it = table(scope).find(id);
    if (it == table(scope).end() || !it->second.snapshot) return nullptr;
    const Entry& e = it->second;
    if (!e.stale() || (e.snapshot->index.size() > options_.sync_rebuild_max_rps && e.built >= e.sync_before)) return e.snapshot;
    return nullptr;
}

std::size_t Service::background_rebuilds() const {
    std::lock_guard lock(mu_);
    return background_rebuilds_;
}

std::shared_ptr<const Snapshot> Service::rebuild(Scope scope, std::int64_t id) {
    std::uint64_t generation = 0;
    {
        // Taken before reading, so a write that commits during the read leaves the entry stale.
        std::lock_guard lock(mu_);
        generation = table(scope)[id].wanted;
    }
    std::vector<store::StoredRp> stored;
    std::string settings;
    try {
        if (scope == Scope::radiomap) {
            store_.get(store::kind("radiomaps"), id);  // NotFound for an unknown id
            stored = store_.rps_of_radiomap(id);
            if (auto s = store_.settings_of_radiomap(id)) settings = std::move(s->settings);
        } else {
            store_.get(store::kind("maps"), id);
            stored = store_.rps_of_map(id);
            settings = common_settings(stored);
        }
    } catch (const store::NotFound&) {
        std::lock_guard lock(mu_);
        table(scope).erase(id);
        throw;
    }
    auto snap = std::make_shared<Snapshot>();
    std::vector<match::IndexedRp> rps;
    rps.reserve(stored.size());
    for (auto& s : stored) {
        if (!snap->rooms_by_floor.count(s.floor_id)) snap->rooms_by_floor[s.floor_id] = store_.rooms_of_floor(s.floor_id);
        rps.push_back({std::move(s.rp), s.floor_id, s.building_id});
    }
    snap->index = match::Index::build(rps);
    snap->settings_text = std::move(settings);
    if (prepare_) prepare_(*snap);
    std::lock_guard lock(mu_);
    const auto it = table(scope).find(id);
    if (it == table(scope).end()) return snap;  // a delete raced the build: nothing to publish to
    Entry& e = it->second;
    if (generation > e.built) {
        e.snapshot = std::move(snap);
        e.built = generation;
    }
    return e.snapshot;
}

std::string Service::common_settings(const std::vector<store::StoredRp>& stored) {
    std::unordered_set<std::int64_t> radiomaps;
    for (const auto& s : stored) radiomaps.insert(s.radiomap_id);
    std::optional<std::string> common;
    for (const auto id : radiomaps) {
        std::string text;
        try {
            if (auto s = store_.settings_of_radiomap(id)) text = std::move(s->settings);
        } catch (const store::NotFound&) {
            // Deleted since the RPs were read: its change marks this map stale again.
        }
        if (common && *common != text) return {};
        common = std::move(text);
    }
    return common.value_or(std::string());
}

void Service::mark_dirty(Scope scope, std::int64_t id, bool sync) {
    {
        std::lock_guard lock(mu_);
        Entry& e = table(scope)[id];
        ++e.wanted;
        if (sync) e.sync_before = e.wanted;
    }
    wake_.notify_one();
}

void Service::mark_all_dirty(bool sync) {
    {
        std::lock_guard lock(mu_);
        for (Table* t : {&radiomaps_, &maps_})
            for (auto& entry : *t) {
                Entry& e = entry.second;
                ++e.wanted;
                if (sync) e.sync_before = e.wanted;
            }
    }
    wake_.notify_one();
}

void Service::on_change(const store::Change& change) {
    if (change.plan) return;  // indexes hold no plan
    const std::string_view kind = change.kind->name;
    if (kind == "rps" || kind == "radiomaps") {
        if (change.radiomap_id) mark_dirty(Scope::radiomap, *change.radiomap_id, change.deleted);
        // Without its map (the write raced a delete of the hierarchy), any map may hold it.
        if (change.map_id) mark_dirty(Scope::map, *change.map_id, change.deleted);
        else mark_all_dirty(change.deleted);
    } else if (kind == "rooms" || change.deleted) {
        // Rooms change symbolic locations; deleting a floor, building or map cascades, and
        // is rare enough that queries may pay a rebuild to never answer from deleted RPs.
        mark_all_dirty(change.deleted);
    }
}

// Pacing: after a round of background rebuilds that took d, the next round starts no sooner
// than pace_factor x d after it finished. Surveyors uploading without pause to a map whose
// rebuilds (its radio map's and the map's index) take d then cost this thread at most
// 1 / (1 + pace_factor) of one core, instead of a core busy re-reading the store; the uploads
// arriving meanwhile coalesce into the next round. Small indexes (d of a few ms) are hardly
// delayed, and queries never wait for this thread (see lookup).
void Service::refresher() {
    std::unique_lock lock(mu_);
    const auto any_stale = [this] {
        for (const auto& entry : radiomaps_)
            if (entry.second.stale()) return true;
        for (const auto& entry : maps_)
            if (entry.second.stale()) return true;
        return false;
    };
    Clock::time_point next_round{};
    while (!stopping_) {
        wake_.wait(lock, [&] { return stopping_ || any_stale(); });
        if (stopping_) break;
        wake_.wait_for(lock, options_.settle, [this] { return stopping_; });
        wake_.wait_until(lock, next_round, [this] { return stopping_; });
        if (stopping_) break;
        std::vector<std::pair<Scope, std::int64_t>> todo;
        for (const Scope scope : {Scope::radiomap, Scope::map})
            for (const auto& entry : table(scope))
                if (entry.second.stale()) todo.emplace_back(scope, entry.first);
        lock.unlock();
        const auto started = Clock::now();
        for (const auto& item : todo) {
            try {
                rebuild(item.first, item.second);
            } catch (const store::NotFound&) {
                // Deleted meanwhile: rebuild already dropped it.
            } catch (const std::exception&) {
                // A failed rebuild leaves the entry stale: retried in the next round.
            }
        }
        const auto finished = Clock::now();
        next_round = finished + std::chrono::duration_cast<Duration>((finished - started) * options_.pace_factor);
        lock.lock();
        background_rebuilds_ += todo.size();
    }
}

}  // namespace locus::localize
