#include "transmitters/transmitter_cache.hpp"

#include "store/kinds.hpp"
#include "transmitters/floor_transmitters.hpp"

namespace locus::transmitters {

TransmitterCache::TransmitterCache(store::Store& store) : store_(store) {
    token_ = store_.subscribe([this](const store::Change& c) { on_change(c); });
}

TransmitterCache::~TransmitterCache() { store_.unsubscribe(token_); }

void TransmitterCache::on_change(const store::Change& c) {
    if (!c.kind) return;
    const auto name = c.kind->name;
    // A transmitter's change names no floor, and deleting a floor (or what holds it) deletes
    // its transmitters by cascade without one each: drop everything, the next read refills.
    const bool holder = name == "maps" || name == "buildings" || name == "floors";
    if (name != "transmitters" && !(holder && c.deleted)) return;
    std::lock_guard lock(mu_);
    floors_.clear();
    ++generation_;
}

std::shared_ptr<const std::vector<store::Record>> TransmitterCache::of_floor(std::int64_t floor_id) {
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mu_);
        if (const auto it = floors_.find(floor_id); it != floors_.end()) return it->second;
        generation = generation_;
    }
    auto read = std::make_shared<const std::vector<store::Record>>(transmitters_of_floor(store_, floor_id));
    std::lock_guard lock(mu_);
    if (generation == generation_) floors_[floor_id] = read;
    return read;
}

}  // namespace locus::transmitters
