#pragma once
// Routing over each map's building graph (locus::plan): every floor with a plan, its walk
// grid and the connectors between floors. A graph is built from the store on the first route
// of a map (about 0.1 s per 10,000 m² floor, docs/routing.md) and kept until a write changes
// a plan or the hierarchy it hangs on; routes then run on the immutable graph with no lock.
//
// Maps build apart: a map's build holds no lock another map waits on, and the requests of a
// map that arrive during its build wait for that one build, not for one another. A graph
// whose estimated memory (plan::building_cost) is past the server's bound is refused before
// anything is built, and the refusal kept until the next write that could change it.
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "locus/plan/route.hpp"
#include "store/store.hpp"

namespace locus::routing {

// A map whose graph would be larger than ServiceOptions::max_graph_bytes.
struct TooLarge : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct ServiceOptions {
    double max_graph_bytes = 192.0 * 1024 * 1024;  // plan::BuildingCost::bytes
    // What builds a graph; empty: plan::build_building. Tests hold a build here to see what
    // waits for it.
    std::function<plan::Building(std::vector<plan::FloorSpec>)> build;
};

class Service {
public:
    explicit Service(store::Store& store, ServiceOptions options = {});
    ~Service();
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // The map's building graph, built first if needed; NotFound for an unknown map, TooLarge
    // for one past the bound. Costs a hash lookup under a mutex when the graph is kept;
    // otherwise a read of the map's plans and the build (or the wait for the build under way).
    std::shared_ptr<const plan::Building> building(std::int64_t map_id);

private:
    using Graph = std::shared_ptr<const plan::Building>;
    // A build under way: the requests of its map that arrive meanwhile wait on `done`.
    struct Build {
        std::promise<Graph> promise;
        std::shared_future<Graph> done = promise.get_future().share();
    };

    void on_change(const store::Change& change);
    Graph build(std::int64_t map_id);  // reads the plans, checks the cost, builds

    store::Store& store_;
    ServiceOptions options_;
    std::size_t subscription_ = 0;
    std::mutex mu_;  // guards the four below, never held while building
    std::unordered_map<std::int64_t, Graph> buildings_;
    std::unordered_map<std::int64_t, std::string> refused_;  // TooLarge's message, until a change
    std::unordered_map<std::int64_t, std::shared_ptr<Build>> builds_;
    std::uint64_t generation_ = 0;  // bumped by every change that may touch a graph
};

}  // namespace locus::routing
