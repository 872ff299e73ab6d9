#include "routing/service.hpp"

#include <cmath>
#include <exception>
#include <utility>

namespace locus::routing {

Service::Service(store::Store& store, ServiceOptions options) : store_(store), options_(options) {
    subscription_ = store_.subscribe([this](const store::Change& change) { on_change(change); });
}

Service::~Service() { store_.unsubscribe(subscription_); }

void Service::on_change(const store::Change& change) {
    const std::string_view kind = change.kind->name;
    // A plan, a floor's level (what instructions say) or a deleted part of the hierarchy.
    if (!change.plan && kind != "floors" && !(change.deleted && (kind == "buildings" || kind == "maps"))) return;
    std::lock_guard lock(mu_);
    buildings_.clear();
    refused_.clear();
    // A build under way read the plans before this write: the requests still waiting for it
    // take its graph (they came before the write), a later one starts its own build.
    builds_.clear();
    ++generation_;
}

Service::Graph Service::build(std::int64_t map_id) {
    std::vector<plan::FloorSpec> floors;
    for (auto& f : store_.plans_of_map(map_id)) floors.push_back({f.floor_id, static_cast<int>(f.level), std::move(f.plan)});
    const plan::BuildingCost cost = plan::building_cost(floors);
    if (cost.bytes > options_.max_graph_bytes) {
        const auto mb = [](double bytes) { return std::to_string(static_cast<long long>(std::ceil(bytes / (1024 * 1024)))); };
        throw TooLarge("map " + std::to_string(map_id) + "'s route graph would take about " + mb(cost.bytes) + " MB (" +
                       std::to_string(floors.size()) + " floors with plans, " + std::to_string(static_cast<long long>(cost.cells)) +
                       " cells of 0.25 m, a distance per cell from each connector and four corners); this server builds at most " +
                       mb(options_.max_graph_bytes) + " MB (--max-route-graph-mb)");
    }
    return std::make_shared<const plan::Building>(options_.build ? options_.build(std::move(floors))
                                                                 : plan::build_building(std::move(floors)));
}

std::shared_ptr<const plan::Building> Service::building(std::int64_t map_id) {
    std::shared_ptr<Build> mine;
    std::shared_future<Graph> under_way;
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mu_);
        if (const auto it = buildings_.find(map_id); it != buildings_.end()) return it->second;
        if (const auto it = refused_.find(map_id); it != refused_.end()) throw TooLarge(it->second);
        if (const auto it = builds_.find(map_id); it != builds_.end()) {
            under_way = it->second->done;
        } else {
            mine = std::make_shared<Build>();
            builds_[map_id] = mine;
            generation = generation_;
        }
    }
    if (under_way.valid()) return under_way.get();  // that build's graph, or its error
    // Ends this map's build under way, whatever happens: later requests find the graph (if no
    // write came in meanwhile), the refusal, or nothing, and the waiters are answered.
    const auto finish = [&](const Graph* graph, const std::string* refusal) {
        std::lock_guard lock(mu_);
        if (const auto it = builds_.find(map_id); it != builds_.end() && it->second == mine) builds_.erase(it);
        if (generation_ != generation) return;
        if (graph) buildings_[map_id] = *graph;
        if (refusal) refused_[map_id] = *refusal;
    };
    try {
        Graph graph = build(map_id);
        finish(&graph, nullptr);
        mine->promise.set_value(graph);
        return graph;
    } catch (const TooLarge& e) {
        const std::string message = e.what();
        finish(nullptr, &message);
        mine->promise.set_exception(std::current_exception());
        throw;
    } catch (...) {
        finish(nullptr, nullptr);
        mine->promise.set_exception(std::current_exception());
        throw;
    }
}

}  // namespace locus::routing
