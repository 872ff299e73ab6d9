// The routing service keeps a map's building graph until a write could change a route: a
// plan replaced or removed, a floor's level, a deleted part of the hierarchy.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace routing_service_test
