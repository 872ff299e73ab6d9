#include "localize/service.hpp"

#include <chrono>
#include <optional>
#include <string>

namespace locus::localize {

Service::Service(store::Store& store, Prepare prepare) : store_(store), prepare_(std::move(prepare)) {
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

std::shared_ptr<const Snapshot> Service::lookup(Scope scope, std::int64_t id) {
    {
        std::lock_guard lock(mu_);
        if (!dirty(scope).count(id)) {
            if (auto it = table(scope).find(id); it != table(scope).end()) return it->second;
        }
    }
    return rebuild(scope, id);
}

std::shared_ptr<const Snapshot> Service::rebuild(Scope scope, std::int64_t id) {
    std::lock_guard build(build_mu_);
    {
        // Cleared before reading, so a write that commits during the read marks it again.
        std::lock_guard lock(mu_);
        dirty(scope).erase(id);
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
    std::shared_ptr<const Snapshot> out = snap;
    std::lock_guard lock(mu_);
    table(scope)[id] = out;
    return out;
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

void Service::mark_dirty(Scope scope, std::int64_t id) {
    {
        std::lock_guard lock(mu_);
        dirty(scope).insert(id);
    }
    wake_.notify_one();
}

void Service::mark_all_dirty() {
    {
        std::lock_guard lock(mu_);
        for (const auto& [id, snap] : radiomaps_) dirty_radiomaps_.insert(id);
        for (const auto& [id, snap] : maps_) dirty_maps_.insert(id);
    }
    wake_.notify_one();
}

void Service::on_change(const store::Change& change) {
    if (change.plan) return;  // indexes hold no plan
    const std::string_view kind = change.kind->name;
    if (kind == "rps" || kind == "radiomaps") {
        if (change.radiomap_id) mark_dirty(Scope::radiomap, *change.radiomap_id);
        // Without its map (the write raced a delete of the hierarchy), any map may hold it.
        if (change.map_id) mark_dirty(Scope::map, *change.map_id);
        else mark_all_dirty();
    } else if (kind == "rooms" || change.deleted) {
        // Rooms change symbolic locations; deleting a floor, building or map cascades.
        mark_all_dirty();
    }
}

void Service::refresher() {
    // Waits for writes to settle a little so a burst (an import) costs one rebuild, not one per row.
    constexpr auto kSettle = std::chrono::milliseconds(50);
    std::unique_lock lock(mu_);
    while (!stopping_) {
        wake_.wait(lock, [this] { return stopping_ || !dirty_radiomaps_.empty() || !dirty_maps_.empty(); });
        if (stopping_) break;
        wake_.wait_for(lock, kSettle, [this] { return stopping_; });
        if (stopping_) break;
        std::vector<std::pair<Scope, std::int64_t>> todo;
        for (auto id : dirty_radiomaps_) todo.emplace_back(Scope::radiomap, id);
        for (auto id : dirty_maps_) todo.emplace_back(Scope::map, id);
        lock.unlock();
        for (const auto& [scope, id] : todo) {
            try {
                rebuild(scope, id);
            } catch (const store::NotFound&) {
                // Deleted meanwhile: rebuild already dropped it.
            } catch (const std::exception&) {
                // A failed background rebuild leaves the entry dirty for the next query to retry.
                mark_dirty(scope, id);
            }
        }
        lock.lock();
    }
}

}  // namespace locus::localize
