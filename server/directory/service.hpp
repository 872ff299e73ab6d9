#pragma once
// Each map's directory (places.hpp), built from the store on the map's first search (tens of
// milliseconds for 10,000 names) and dropped on any write to rooms, POIs, plans, floors,
// buildings or maps: the simple rule, since such writes are rare next to searches and a
// rebuild is cheap. Scans and radio maps leave it alone. Searches then run on the immutable
// directory with no lock.
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "directory/places.hpp"
#include "store/store.hpp"

namespace locus::directory {

class Service {
public:
    explicit Service(store::Store& store);
    ~Service();
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // The map's directory, built first if needed; NotFound for an unknown map.
    std::shared_ptr<const MapDirectory> of_map(std::int64_t map_id);

private:
    void on_change(const store::Change& change);

    store::Store& store_;
    std::size_t subscription_ = 0;
    std::mutex mu_;  // guards the two below, never held while building
    std::unordered_map<std::int64_t, std::shared_ptr<const MapDirectory>> maps_;
    std::uint64_t generation_ = 0;  // bumped by every change that may touch a directory
    std::mutex build_mu_;           // one build at a time
};

}  // namespace locus::directory
