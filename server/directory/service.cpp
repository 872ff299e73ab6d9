#include "directory/service.hpp"

namespace locus::directory {

Service::Service(store::Store& store) : store_(store) {
    subscription_ = store_.subscribe([this](const store::Change& change) { on_change(change); });
}

Service::~Service() { store_.unsubscribe(subscription_); }

void Service::on_change(const store::Change& change) {
    const std::string_view kind = change.kind->name;
    if (kind == "radiomaps" || kind == "rps" || kind == "tracks") return;  // the directory holds none
    std::lock_guard lock(mu_);
    maps_.clear();
    ++generation_;
}

std::shared_ptr<const MapDirectory> Service::of_map(std::int64_t map_id) {
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mu_);
        if (auto it = maps_.find(map_id); it != maps_.end()) return it->second;
    }
    std::lock_guard build(build_mu_);
    {
        // Another request may have built it while this one waited.
        std::lock_guard lock(mu_);
        if (auto it = maps_.find(map_id); it != maps_.end()) return it->second;
        generation = generation_;
    }
    auto built = std::make_shared<const MapDirectory>(build_directory(store_.directory_of_map(map_id)));
    std::lock_guard lock(mu_);
    // Kept only if no write came in while it was read: that write's directory is built next time.
    if (generation_ == generation) maps_[map_id] = built;
    return built;
}

}  // namespace locus::directory
