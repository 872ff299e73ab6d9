#pragma once
// Routing over each map's building graph (locus::plan): every floor with a plan, its walk
// grid and the connectors between floors. A graph is built from the store on the first route
// of a map (about 0.1 s per 10,000 m² floor, docs/routing.md) and kept until a write changes
// a plan or the hierarchy it hangs on; routes then run on the immutable graph with no lock.
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "locus/plan/route.hpp"
#include "store/store.hpp"

namespace locus::routing {

class Service {
public:
    explicit Service(store::Store& store);
    ~Service();
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // The map's building graph, built first if needed; NotFound for an unknown map.
    std::shared_ptr<const plan::Building> building(std::int64_t map_id);

private:
    void on_change(const store::Change& change);

    store::Store& store_;
    std::size_t subscription_ = 0;
    std::mutex mu_;  // guards the two below, never held while building
    std::unordered_map<std::int64_t, std::shared_ptr<const plan::Building>> buildings_;
    std::uint64_t generation_ = 0;  // bumped by every change that may touch a graph
    std::mutex build_mu_;           // one build at a time
};

}  // namespace locus::routing
