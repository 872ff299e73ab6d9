// The ranging localize's per-floor transmitter cache over a real SQLite store: one read per
// floor until a write that can change its transmitters, whichever call made it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "transmitters/transmitter_cache.hpp"
#include "store/sql_store.hpp"
#include "temp_dir.hpp"

namespace transmitter_cache_test {
namespace {

using locus::transmitters::TransmitterCache;
using locus::store::Fields;
using locus::store::kind;
using locus::store::SqlStore;

using locus::testing::TempDir;
Fields tx(const std::string& bssid, double x) {
    return {{"type", std::string("wifi")}, {"bssid", bssid}, {"x", x}, {"y", 1.0}, {"tx_power", -40.0}};
}

TEST(TransmitterCache, ReadsAFloorOnceAndFollowsEveryChange) {
    TempDir t{"txcache"};
    SqlStore s(t.path());
    const auto map = s.create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
    const auto building = s.create(kind("buildings"), map, {{"name", "B"}}).id;
    const auto floor = s.create(kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 20.0}, {"height", 10.0}}).id;
    const auto other = s.create(kind("floors"), building, {{"name", "G"}, {"level", 1}, {"width", 20.0}, {"height", 10.0}}).id;
    const auto a = s.create(kind("transmitters"), floor, tx("aa:00:00:00:00:01", 1.0)).id;
    TransmitterCache cache(s);

    const auto first = cache.of_floor(floor);
    ASSERT_EQ(first->size(), 1u);
    EXPECT_EQ(cache.of_floor(floor), first);  // the same snapshot: no second read
    EXPECT_TRUE(cache.of_floor(other)->empty());

    s.update(kind("transmitters"), a, {{"x", 5.0}});
    const auto moved = cache.of_floor(floor);
    EXPECT_NE(moved, first);
    EXPECT_DOUBLE_EQ(moved->at(0).fields.get<double>("x"), 5.0);
    EXPECT_DOUBLE_EQ(first->at(0).fields.get<double>("x"), 1.0);  // a reader's snapshot stays whole

    s.write_rows(kind("transmitters"), other, {{std::nullopt, tx("aa:00:00:00:00:02", 2.0)}});
    EXPECT_EQ(cache.of_floor(other)->size(), 1u);
    s.remove(kind("transmitters"), a);
    EXPECT_TRUE(cache.of_floor(floor)->empty());

    // A change of anything else keeps the snapshot.
    const auto kept = cache.of_floor(other);
    s.create(kind("radiomaps"), floor, {{"name", "R"}});
    EXPECT_EQ(cache.of_floor(other), kept);
    // Deleting the floor takes its transmitters (by cascade): an unknown floor is NotFound.
    s.remove(kind("floors"), other);
    EXPECT_THROW(cache.of_floor(other), locus::store::NotFound);
}

}  // namespace
}  // namespace transmitter_cache_test
