#include "transmitters/transmitter_cache.hpp"

#include "store/kinds.hpp"
#include "transmitters/floor_transmitters.hpp"

namespace locus::transmitters {

namespace {

store::FloorDrop transmitter_drops(const store::Change& c) {
    if (!c.kind) return store::FloorDrop::none;
    const auto& name = c.kind->name;
    // A transmitter's change names no floor, and deleting a floor (or what holds it) deletes
    // its transmitters by cascade without one each: drop everything, the next read refills.
    const bool holder = name == "maps" || name == "buildings" || name == "floors";
    return name == "transmitters" || (holder && c.deleted) ? store::FloorDrop::all : store::FloorDrop::none;
}

std::shared_ptr<const std::vector<store::Record>> read_transmitters(store::Store& store, std::int64_t floor_id) {
    return std::make_shared<const std::vector<store::Record>>(transmitters_of_floor(store, floor_id));
}

}  // namespace

TransmitterCache::TransmitterCache(store::Store& store) : cache_(store, read_transmitters, transmitter_drops) {}

}  // namespace locus::transmitters
