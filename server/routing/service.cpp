#include "routing/service.hpp"

namespace locus::routing {

Service::Service(store::Store& store) : store_(store) {
    subscription_ = store_.subscribe([this](const store::Change& change) { on_change(change); });
}

Service::~Service() { store_.unsubscribe(subscription_); }

void Service::on_change(const store::Change& change) {
    const std::string_view kind = change.kind->name;
    // A plan, a floor's level (what instructions say) or a deleted part of the hierarchy.
    if (!change.plan && kind != "floors" && !(change.deleted && (kind == "buildings" || kind == "maps"))) return;
    std::lock_guard lock(mu_);
    buildings_.clear();
    ++generation_;
}

std::shared_ptr<const plan::Building> Service::building(std::int64_t map_id) {
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mu_);
        if (auto it = buildings_.find(map_id); it != buildings_.end()) return it->second;
        generation = generation_;
    }
    std::lock_guard build(build_mu_);
    {
        // Another request may have built it while this one waited.
        std::lock_guard lock(mu_);
        if (auto it = buildings_.find(map_id); it != buildings_.end()) return it->second;
        generation = generation_;
    }
    std::vector<plan::FloorSpec> floors;
    for (auto& f : store_.plans_of_map(map_id))
        floors.push_back({f.floor_id, static_cast<int>(f.level), std::move(f.plan)});
    auto built = std::make_shared<const plan::Building>(plan::build_building(std::move(floors)));
    std::lock_guard lock(mu_);
    // Kept only if no write came in while it was read: that write's graph is built next time.
    if (generation_ == generation) buildings_[map_id] = built;
    return built;
}

}  // namespace locus::routing
