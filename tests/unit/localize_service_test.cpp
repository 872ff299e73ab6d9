// The localize service follows the store's change feed, whichever code wrote: an index
// reflects every committed write the next time it is looked up, with no HTTP layer involved.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "localize/service.hpp"
#include "store/sql_store.hpp"

namespace localize_service_test {
namespace {

using namespace locus;
using locus::store::kind;
using Scope = locus::localize::Service::Scope;

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

// A big index a write made stale is served as it was while the background rebuilds it: a
// query does not wait for a full rebuild. "Big" is every index here (limit 0), and the
// background never runs (an hour's settle), so the old snapshot must come back untouched.
TEST(LocalizeService, AStaleBigIndexIsServedWithoutRebuilding) {
    World w;
    w.rp("a", 1.0, 1.0);
    std::atomic<int> prepared{0};
    localize::Service::Options options;
    options.sync_rebuild_max_rps = 0;
    options.settle = std::chrono::hours(1);
    localize::Service service(w.store, [&](localize::Snapshot&) { ++prepared; }, options);
    const auto before = service.lookup(Scope::radiomap, w.radiomap);
    const int built = prepared.load();

    w.rp("b", 5.0, 1.0);
    const auto after = service.lookup(Scope::radiomap, w.radiomap);
    EXPECT_EQ(after, before);
    EXPECT_EQ(after->index.size(), 1u);
    EXPECT_EQ(service.lookup(Scope::map, w.map)->index.size(), 1u);
    EXPECT_EQ(prepared.load(), built);
    EXPECT_EQ(service.background_rebuilds(), 0u);
}

// ...and the background does catch up: the new RP shows without any query rebuilding.
TEST(LocalizeService, TheBackgroundServesTheNewDataEventually) {
    World w;
    w.rp("a", 1.0, 1.0);
    localize::Service::Options options;
    options.sync_rebuild_max_rps = 0;
    options.settle = std::chrono::milliseconds(1);
    localize::Service service(w.store, {}, options);
    ASSERT_EQ(service.lookup(Scope::radiomap, w.radiomap)->index.size(), 1u);

    w.rp("b", 5.0, 1.0);
    // Bounded poll, not a timed assertion: the bound only stops a broken refresher hanging ctest.
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while ((service.lookup(Scope::radiomap, w.radiomap)->index.size() != 2u || service.lookup(Scope::map, w.map)->index.size() != 2u) &&
           std::chrono::steady_clock::now() < give_up)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    EXPECT_EQ(service.lookup(Scope::radiomap, w.radiomap)->index.size(), 2u);
    EXPECT_EQ(service.lookup(Scope::map, w.map)->index.size(), 2u);
    EXPECT_GE(service.background_rebuilds(), 1u);
}

// A small index keeps read-your-writes: with the background held off (an hour's settle), the
// next query after a write rebuilds it itself, for the radio map and its map alike.
TEST(LocalizeService, SmallIndexesKeepReadYourWrites) {
    World w;
    w.rp("a", 1.0, 1.0);
    localize::Service::Options options;
    options.settle = std::chrono::hours(1);
    localize::Service service(w.store, {}, options);
    ASSERT_EQ(service.lookup(Scope::radiomap, w.radiomap)->index.size(), 1u);
    for (int i = 0; i < 3; ++i) {
        const std::string name = std::to_string(i);
        w.rp(name.c_str(), 2.0 + i, 1.0);
        EXPECT_EQ(service.lookup(Scope::radiomap, w.radiomap)->index.size(), 2u + i);
        EXPECT_EQ(service.lookup(Scope::map, w.map)->index.size(), 2u + i);
    }
    EXPECT_EQ(service.background_rebuilds(), 0u);
}

// Deletes are rare and must not be answered from: a big stale index is rebuilt by the query
// after one, so a deleted radio map is not found and a deleted RP is gone at once.
TEST(LocalizeService, DeletesShowAtOnceEvenInBigIndexes) {
    World w;
    w.rp("a", 1.0, 1.0);
    const auto b = w.rp("b", 5.0, 1.0);
    localize::Service::Options options;
    options.sync_rebuild_max_rps = 0;
    options.settle = std::chrono::hours(1);
    localize::Service service(w.store, {}, options);
    ASSERT_EQ(service.lookup(Scope::map, w.map)->index.size(), 2u);

    w.store.remove(kind("rps"), b);
    EXPECT_EQ(service.lookup(Scope::radiomap, w.radiomap)->index.size(), 1u);
    EXPECT_EQ(service.lookup(Scope::map, w.map)->index.size(), 1u);
    w.store.remove(kind("radiomaps"), w.radiomap);
    EXPECT_THROW(service.lookup(Scope::radiomap, w.radiomap), store::NotFound);
    EXPECT_EQ(service.lookup(Scope::map, w.map)->index.size(), 0u);
}

}  // namespace
}  // namespace localize_service_test
