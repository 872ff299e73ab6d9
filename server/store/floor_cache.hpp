#pragma once
// A value per floor read from the store once and kept until the change feed says it may have
// changed: what the floor caches (floors/floor_geo.hpp, floors/floor_places_cache.hpp,
// transmitters/transmitter_cache.hpp) share, each giving how a floor's value is read and which
// changes drop what. A read costs one hash lookup under a mutex once kept; a miss reads the store
// outside the lock, and a read that raced with a change (the generation moved) is answered but
// not kept.
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <utility>

#include "store/store.hpp"

namespace locus::store {

// What a change does to the cache: nothing, drops the floor it names, or drops every floor (a
// change that names no floor, or a cascade that sends no change per floor).
enum class FloorDrop { none, floor, all };

template <class T>
class FloorCache {
public:
    // load(store, floor_id): the floor's value (null kept too); its exceptions pass, nothing kept.
    using Load = std::function<std::shared_ptr<const T>(Store&, std::int64_t floor_id)>;
    using Drops = FloorDrop (*)(const Change&);

    FloorCache(Store& store, Load load, Drops drops) : store_(store), load_(std::move(load)), drops_(drops) {
        token_ = store_.subscribe([this](const Change& c) { on_change(c); });
    }
    ~FloorCache() { store_.unsubscribe(token_); }
    FloorCache(const FloorCache&) = delete;
    FloorCache& operator=(const FloorCache&) = delete;

    std::shared_ptr<const T> of_floor(std::int64_t floor_id) {
        std::uint64_t generation = 0;
        {
            std::lock_guard lock(mu_);
            if (const auto it = floors_.find(floor_id); it != floors_.end()) return it->second;
            generation = generation_;
        }
        auto read = load_(store_, floor_id);
        std::lock_guard lock(mu_);
        if (generation == generation_) floors_[floor_id] = read;
        return read;
    }

private:
    void on_change(const Change& c) {
        const FloorDrop drop = drops_(c);
        if (drop == FloorDrop::none) return;
        std::lock_guard lock(mu_);
        if (drop == FloorDrop::floor) floors_.erase(c.id);
        else floors_.clear();
        ++generation_;
    }

    Store& store_;
    Load load_;
    Drops drops_;
    std::mutex mu_;
    std::unordered_map<std::int64_t, std::shared_ptr<const T>> floors_;
    std::uint64_t generation_ = 0;  // bumped by every invalidation
    std::size_t token_ = 0;
};

}  // namespace locus::store
