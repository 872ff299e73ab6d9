// The localize service follows the store's change feed, whichever code wrote: an index
// reflects every committed write the next time it is looked up, with no HTTP layer involved.
#include <gtest/gtest.h>

#include <atomic>

#include "localize/service.hpp"
#include "store/sql_store.hpp"

using namespace locus;
using locus::store::kind;
using Scope = locus::localize::Service::Scope;

namespace {

struct World {
    store::SqlStore store{":memory:"};
    std::int64_t map = 0, floor = 0, radiomap = 0;
    World() {
        map = store.create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
        const auto building = store.create(kind("buildings"), map, {{"name", "B"}}).id;
        floor = store.create(kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 20.0}, {"height", 10.0}}).id;
        radiomap = store.create(kind("radiomaps"), floor, {{"name", "R"}}).id;
    }
    std::int64_t rp(const char* name, double x, double y) {
        const auto id = store.create(kind("rps"), radiomap, {{"name", name}, {"x", x}, {"y", y}}).id;
        store.merge_scans(id, {std::nullopt, {{"wifi", "ap", RssStats{-50.0, 1.0, 3}}}, 3});
        return id;
    }
};

}  // namespace

TEST(LocalizeService, IndexesFollowWritesMadeStraightToTheStore) {
    World w;
    w.rp("a", 1.0, 1.0);
    std::atomic<int> prepared{0};
    localize::Service service(w.store, [&](localize::Snapshot&) { ++prepared; });
    EXPECT_EQ(service.lookup(Scope::radiomap, w.radiomap)->index.size(), 1u);
    EXPECT_EQ(service.lookup(Scope::map, w.map)->index.size(), 1u);
    EXPECT_GE(prepared.load(), 2);

    w.rp("b", 5.0, 1.0);
    EXPECT_EQ(service.lookup(Scope::radiomap, w.radiomap)->index.size(), 2u);
    EXPECT_EQ(service.lookup(Scope::map, w.map)->index.size(), 2u);

    EXPECT_TRUE(service.lookup(Scope::map, w.map)->rooms_by_floor.at(w.floor).empty());
    w.store.create(kind("rooms"), w.floor, store::Fields({{"name", "Hall"}}, std::vector<Rect>{{0, 0, 10, 10}}));
    ASSERT_EQ(service.lookup(Scope::map, w.map)->rooms_by_floor.at(w.floor).size(), 1u);

    w.store.remove(kind("radiomaps"), w.radiomap);
    EXPECT_THROW(service.lookup(Scope::radiomap, w.radiomap), store::NotFound);
    EXPECT_EQ(service.lookup(Scope::map, w.map)->index.size(), 0u);
}

TEST(LocalizeService, AnUnknownIdIsNotFound) {
    World w;
    localize::Service service(w.store);
    EXPECT_THROW(service.lookup(Scope::radiomap, 999), store::NotFound);
    EXPECT_THROW(service.lookup(Scope::map, 999), store::NotFound);
}

// Once the service is gone, writes go on without calling it.
TEST(LocalizeService, StopsFollowingWhenDestroyed) {
    World w;
    { localize::Service service(w.store); }
    EXPECT_NO_THROW(w.rp("after", 2.0, 2.0));
}
