// Store::write_rows, what a transmitter fit's ?apply=true writes through: all rows or none.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "store/sql_store.hpp"
#include "temp_dir.hpp"

namespace store_write_rows_test {
namespace {

using locus::store::Fields;
using locus::store::kind;
using locus::store::RowWrite;
using locus::store::SqlStore;

using locus::testing::TempDir;
std::int64_t make_floor(SqlStore& s) {
    const auto map = s.create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
    const auto building = s.create(kind("buildings"), map, {{"name", "B"}}).id;
    return s.create(kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 20.0}, {"height", 10.0}}).id;
}

Fields tx(const std::string& bssid, double x) {
    return {{"type", std::string("wifi")}, {"bssid", bssid}, {"x", x}, {"y", 1.0}, {"tx_power", -40.0}};
}

TEST(StoreWriteRows, CreatesAndUpdatesInOrderAndPublishesEach) {
    TempDir t{"rows"};
    SqlStore s(t.path());
    const auto floor = make_floor(s);
    const auto a = s.create(kind("transmitters"), floor, tx("aa:00:00:00:00:01", 1.0)).id;
    int published = 0;
    s.subscribe([&](const locus::store::Change& c) { published += c.kind == &kind("transmitters"); });
    const auto rows = s.write_rows(kind("transmitters"), floor,
                                   {RowWrite{a, {{"x", 7.5}}}, RowWrite{std::nullopt, tx("aa:00:00:00:00:02", 3.0)}});
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].id, a);
    EXPECT_DOUBLE_EQ(rows[0].fields.get<double>("x"), 7.5);
    EXPECT_NE(rows[1].id, a);
    EXPECT_EQ(rows[1].fields.get<std::string>("bssid"), "aa:00:00:00:00:02");
    EXPECT_EQ(published, 2);
    EXPECT_EQ(s.list(kind("transmitters"), floor, 10, 0).total, 2);
}

TEST(StoreWriteRows, ARefusedRowMidwayLeavesEveryRowAsItWas) {
    TempDir t{"rows"};
    SqlStore s(t.path());
    const auto floor = make_floor(s);
    const auto a = s.create(kind("transmitters"), floor, tx("aa:00:00:00:00:01", 1.0)).id;
    s.create(kind("transmitters"), floor, tx("aa:00:00:00:00:09", 2.0));
    int published = 0;
    s.subscribe([&](const locus::store::Change&) { ++published; });
    // The update of a and the new row come first; the third repeats a stored (type, bssid).
    EXPECT_THROW(s.write_rows(kind("transmitters"), floor,
                              {RowWrite{a, {{"x", 7.5}, {"tx_power", -55.0}}},
                               RowWrite{std::nullopt, tx("aa:00:00:00:00:02", 3.0)},
                               RowWrite{std::nullopt, tx("aa:00:00:00:00:09", 4.0)}}),
                 locus::store::Conflict);
    const auto kept = s.get(kind("transmitters"), a);
    EXPECT_DOUBLE_EQ(kept.fields.get<double>("x"), 1.0);
    EXPECT_DOUBLE_EQ(kept.fields.get<double>("tx_power"), -40.0);
    EXPECT_EQ(s.list(kind("transmitters"), floor, 10, 0).total, 2);
    EXPECT_EQ(published, 0);
    // An update of a row that is gone refuses the batch the same way.
    EXPECT_THROW(s.write_rows(kind("transmitters"), floor,
                              {RowWrite{std::nullopt, tx("aa:00:00:00:00:03", 3.0)}, RowWrite{a + 100, {{"x", 2.0}}}}),
                 locus::store::NotFound);
    EXPECT_EQ(s.list(kind("transmitters"), floor, 10, 0).total, 2);
}

}  // namespace
}  // namespace store_write_rows_test
