// The routing service keeps a map's building graph until a write could change a route: a
// plan replaced or removed, a floor's level, a deleted part of the hierarchy. Maps build
// apart (a build held open in the test shows who waits for it), and a graph past the memory
// bound is refused before it is built.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <string>
#include <thread>

#include "routing/service.hpp"
#include "store/sql_store.hpp"

namespace routing_service_test {
namespace {

using namespace locus;
using locus::store::kind;

plan::Plan corridor(double length) {
    plan::Plan p;
    plan::Space s;
    s.name = "Corridor";
    s.shape.outer = {{0, 0}, {length, 0}, {length, 3}, {0, 3}, {0, 0}};
    p.spaces.push_back(s);
    return p;
}

TEST(RoutingService, AGraphIsKeptUntilAPlanOrTheHierarchyChanges) {
    store::SqlStore db(":memory:");
    const auto map = db.create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
    const auto building = db.create(kind("buildings"), map, {{"name", "B"}}).id;
    const auto floor = db.create(kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 50.0}, {"height", 3.0}}).id;
    routing::Service service(db);
    EXPECT_TRUE(service.building(map)->floors.empty());  // no plan yet

    db.put_plan(floor, corridor(10), {});
    const auto first = service.building(map);
    ASSERT_EQ(first->floors.size(), 1u);
    EXPECT_EQ(service.building(map), first);  // kept

    // Writes that cannot change a route leave it.
    db.create(kind("pois"), floor, {{"name", "P"}, {"x", 1.0}, {"y", 1.0}});
    EXPECT_EQ(service.building(map), first);

    db.put_plan(floor, corridor(40), {});
    const auto second = service.building(map);
    EXPECT_NE(second, first);
    const auto far = plan::route(*second, {floor, {1, 1.5}}, {floor, {35, 1.5}});
    EXPECT_EQ(far.status, plan::RouteStatus::ok);
    EXPECT_NEAR(far.length_m, 34.0, 0.5);

    db.update(kind("floors"), floor, {{"level", 2}});
    const auto third = service.building(map);
    EXPECT_NE(third, second);
    EXPECT_EQ(third->floors.at(0).level, 2);

    db.remove_plan(floor);
    EXPECT_TRUE(service.building(map)->floors.empty());
    EXPECT_THROW(service.building(999), store::NotFound);
}

// A map named `name` with one floor whose plan is `plan`; the floor's id in `floor`.
std::int64_t map_with(store::SqlStore& db, const std::string& name, const plan::Plan& plan, std::int64_t& floor) {
    const auto map = db.create(kind("maps"), std::nullopt, {{"name", name}}).id;
    const auto building = db.create(kind("buildings"), map, {{"name", "B"}}).id;
    floor = db.create(kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 50.0}, {"height", 3.0}}).id;
    db.put_plan(floor, plan, {});
    return map;
}

// A build the test holds open: the builder of the floor `held` waits until release().
struct HeldBuild {
    std::int64_t held = 0;
    std::promise<void> entered, released;
    std::shared_future<void> go = released.get_future().share();
    std::atomic<int> builds_of_held{0}, builds{0};

    routing::ServiceOptions options() {
        routing::ServiceOptions o;
        o.build = [this](std::vector<plan::FloorSpec> floors) {
            ++builds;
            if (!floors.empty() && floors[0].floor_id == held && builds_of_held++ == 0) {
                entered.set_value();
                go.wait();
            }
            return plan::build_building(std::move(floors));
        };
        return o;
    }
    void release() { released.set_value(); }
};

TEST(RoutingService, AMapsBuildHoldsNoOtherMapAndItsOwnRequestsShareIt) {
    store::SqlStore db(":memory:");
    std::int64_t floor_a = 0, floor_b = 0;
    const auto a = map_with(db, "A", corridor(30), floor_a), b = map_with(db, "B", corridor(10), floor_b);
    HeldBuild hold;
    hold.held = floor_a;
    routing::Service service(db, hold.options());

    auto first = std::async(std::launch::async, [&] { return service.building(a); });
    hold.entered.get_future().wait();  // map a's build is under way, and stays so
    auto second = std::async(std::launch::async, [&] { return service.building(a); });
    // Another map's graph is built and answered meanwhile.
    auto other = std::async(std::launch::async, [&] { return service.building(b); });
    const bool other_done = other.wait_for(std::chrono::seconds(20)) == std::future_status::ready;
    EXPECT_TRUE(other_done) << "map b waited for map a's build";
    // The second request of map a waits for the build under way; it does not start its own.
    EXPECT_EQ(second.wait_for(std::chrono::milliseconds(50)), std::future_status::timeout);
    hold.release();
    const auto graph = first.get();
    EXPECT_EQ(second.get(), graph);
    ASSERT_EQ(graph->floors.size(), 1u);
    EXPECT_EQ(graph->floors[0].floor_id, floor_a);
    if (other_done) {
        EXPECT_EQ(other.get()->floors.at(0).floor_id, floor_b);
    }
    EXPECT_EQ(hold.builds_of_held.load(), 1);
    EXPECT_EQ(service.building(a), graph);  // kept
    EXPECT_EQ(hold.builds.load(), 2);
}

TEST(RoutingService, AWriteDuringABuildIsBuiltByTheNextRequest) {
    store::SqlStore db(":memory:");
    std::int64_t floor = 0;
    const auto map = map_with(db, "M", corridor(30), floor);
    HeldBuild hold;
    hold.held = floor;
    routing::Service service(db, hold.options());
    auto first = std::async(std::launch::async, [&] { return service.building(map); });
    hold.entered.get_future().wait();
    db.put_plan(floor, corridor(40), {});  // after the build read the plans
    // A request after the write starts a build of its own, on the new plan.
    const auto after = service.building(map);
    hold.release();
    const auto before = first.get();
    EXPECT_NE(after, before);
    EXPECT_EQ(plan::route(*after, {floor, {1, 1.5}}, {floor, {38, 1.5}}).status, plan::RouteStatus::ok);
    EXPECT_NE(plan::route(*before, {floor, {1, 1.5}}, {floor, {38, 1.5}}).status, plan::RouteStatus::ok);
    EXPECT_EQ(service.building(map), after);  // the one built after the write is kept
}

TEST(RoutingService, AGraphPastTheBoundIsRefusedUnbuiltUntilAWriteShrinksIt) {
    store::SqlStore db(":memory:");
    std::int64_t floor = 0;
    // 400 m × 3 m: 1,600 × 12 cells of 0.25 m, four corner landmarks and no connector, 38 bytes
    // a cell: 729,600 bytes. 40 m: 72,960 bytes.
    const auto map = map_with(db, "M", corridor(400), floor);
    std::atomic<int> builds{0};
    routing::ServiceOptions options;
    options.max_graph_bytes = 500'000;
    options.build = [&](std::vector<plan::FloorSpec> floors) {
        ++builds;
        return plan::build_building(std::move(floors));
    };
    routing::Service service(db, options);
    try {
        service.building(map);
        FAIL() << "a graph of about 0.7 MB was built under a 0.5 MB bound";
    } catch (const routing::TooLarge& e) {
        const std::string why = e.what();
        EXPECT_NE(why.find("map " + std::to_string(map) + "'s route graph would take about 1 MB"), std::string::npos) << why;
        EXPECT_NE(why.find("19200 cells"), std::string::npos) << why;
        EXPECT_NE(why.find("--max-route-graph-mb"), std::string::npos) << why;
    }
    EXPECT_THROW(service.building(map), routing::TooLarge);  // still, until a write
    EXPECT_EQ(builds.load(), 0);
    db.put_plan(floor, corridor(40), {});
    EXPECT_EQ(service.building(map)->floors.size(), 1u);
    EXPECT_EQ(builds.load(), 1);
}

}  // namespace
}  // namespace routing_service_test
