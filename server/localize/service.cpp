#include "localize/service.hpp"

#include <chrono>
#include <string>
#include <tuple>

#include "http/api_error.hpp"
#include "http/app.hpp"
#include "http/validation.hpp"
#include "localize/request.hpp"

namespace locus::localize {

using nlohmann::json;

Service::Service(store::Repository& repo) : repo_(repo) {
    std::unordered_set<std::int64_t> maps;
    for (const auto id : repo_.radiomap_ids()) {
        rebuild(Scope::radiomap, id);
        maps.insert(repo_.map_of_radiomap(id));
    }
    for (const auto id : maps) rebuild(Scope::map, id);
    worker_ = std::thread([this] { refresher(); });
}

Service::~Service() {
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
    try {
        if (scope == Scope::radiomap) {
            repo_.get(store::kind("radiomaps"), id);  // NotFound for an unknown id
            stored = repo_.rps_of_radiomap(id);
        } else {
            repo_.get(store::kind("maps"), id);
            stored = repo_.rps_of_map(id);
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
        if (!snap->rooms_by_floor.count(s.floor_id)) snap->rooms_by_floor[s.floor_id] = repo_.rooms_of_floor(s.floor_id);
        rps.push_back({std::move(s.rp), s.floor_id, s.building_id});
    }
    snap->index = match::Index::build(rps);
    prepare_answers(*snap);
    std::shared_ptr<const Snapshot> out = snap;
    std::lock_guard lock(mu_);
    table(scope)[id] = out;
    return out;
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

void Service::on_write(std::string_view kind, const json& row, bool deleted) {
    try {
        if (kind == "rps") {
            const auto rm = row.at("radiomap_id").get<std::int64_t>();
            mark_dirty(Scope::radiomap, rm);
            mark_dirty(Scope::map, repo_.map_of_radiomap(rm));
        } else if (kind == "radiomaps") {
            const auto id = row.at("id").get<std::int64_t>();
            mark_dirty(Scope::radiomap, id);
            if (deleted) mark_all_dirty();  // its map lost RPs; which map is gone with the row
            else mark_dirty(Scope::map, repo_.map_of_radiomap(id));
        } else if (kind == "rooms" || deleted) {
            // Rooms change symbolic locations; deleting a floor, building or map cascades.
            mark_all_dirty();
        }
    } catch (const std::exception&) {
        // The row's map could not be read (gone, or a storage fault after the write committed):
        // the write stands, so rebuild everything rather than answer the client with an error.
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

void Service::install(http::App& app) {
    app.on_write([this](const store::Kind& kind, const json& row, bool deleted) { on_write(kind.name, row, deleted); });
    for (const auto& [collection, what, scope] : {std::tuple{"radiomaps", "radiomap", Scope::radiomap},
                                                  std::tuple{"maps", "map", Scope::map}}) {
        app.server().Post("/v1/" + std::string(collection) + R"(/(\d+)/localize)",
                          // Init-captures: clang before 16 cannot capture structured bindings.
                          [this, what = what, scope = scope](const httplib::Request& req, httplib::Response& res) {
                              http::App::guarded(req, res, [&] {
                                  const auto id = http::parse_id(req.matches[1].str(), what);
                                  const auto request = parse_localize_request(req.body);
                                  // Moved in: set_content would copy the answer. As set_content
                                  // does, any earlier Content-Type goes.
                                  res.body = answer(*lookup(scope, id), request);
                                  res.headers.erase("Content-Type");
                                  res.set_header("Content-Type", "application/json");
                              });
                          });
    }
}

}  // namespace locus::localize
