#pragma once
// The floors' transmitters for the ranging localize and a thin client's ranged scans: read from
// the store once per floor and kept until the change feed says they may have changed, so a
// localize by ranging does no transmitter query (the fingerprint matchers keep their
// snapshots the same way).
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "store/store.hpp"

namespace locus::transmitters {

class TransmitterCache {
public:
    explicit TransmitterCache(store::Store& store);
    ~TransmitterCache();
    TransmitterCache(const TransmitterCache&) = delete;
    TransmitterCache& operator=(const TransmitterCache&) = delete;

    // The floor's transmitters by id, as the store has them (NotFound for an unknown floor).
    std::shared_ptr<const std::vector<store::Record>> of_floor(std::int64_t floor_id);

private:
    void on_change(const store::Change& change);

    store::Store& store_;
    std::mutex mu_;
    std::map<std::int64_t, std::shared_ptr<const std::vector<store::Record>>> floors_;
    // Bumped by every invalidation: a read that raced with a write is not kept.
    std::uint64_t generation_ = 0;
    std::size_t token_ = 0;
};

}  // namespace locus::transmitters
