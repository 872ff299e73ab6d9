#pragma once
// The floors' transmitters for the ranging localize and a thin client's ranged scans: read from
// the store once per floor and kept until the change feed says they may have changed, so a
// localize by ranging does no transmitter query (the fingerprint matchers keep their
// snapshots the same way).
#include <cstdint>
#include <memory>
#include <vector>

#include "store/floor_cache.hpp"
#include "store/store.hpp"

namespace locus::transmitters {

class TransmitterCache {
public:
    explicit TransmitterCache(store::Store& store);

    // The floor's transmitters by id, as the store has them (NotFound for an unknown floor).
    std::shared_ptr<const std::vector<store::Record>> of_floor(std::int64_t floor_id) { return cache_.of_floor(floor_id); }

private:
    store::FloorCache<std::vector<store::Record>> cache_;
};

}  // namespace locus::transmitters
