// The SQLite store on a real file: migrations, CRUD, merge, cascade, snapshots.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "store/migrations.hpp"
#include "http/crud/store_json.hpp"
#include "store/sql_store.hpp"
#include "temp_dir.hpp"

namespace store_test {
namespace {

using locus::store::SqlStore;
using locus::store::Fields;
using locus::store::kind;
using nlohmann::json;

using locus::testing::TempDir;
struct Chain {
    long long map, building, floor, radiomap, rp;
};

Chain make_chain(SqlStore& repo) {
    Chain c{};
    c.map = repo.create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
    c.building = repo.create(kind("buildings"), c.map, {{"name", "B"}}).id;
    c.floor = repo.create(kind("floors"), c.building, {{"name", "F"}, {"level", 0}, {"width", 10.0}, {"height", 5.0}}).id;
    c.radiomap = repo.create(kind("radiomaps"), c.floor, {{"name", "R"}}).id;
    c.rp = repo.create(kind("rps"), c.radiomap, {{"name", "p"}, {"x", 1.0}, {"y", 2.0}}).id;
    return c;
}

TEST(Store, MigratesToTheLatestVersionOnceAndKeepsData) {
    TempDir t{"store"};
    {
        SqlStore repo(t.path());
        repo.create(kind("maps"), std::nullopt, {{"name", "kept"}});
    }
    locus::store::Db db(t.path());
    EXPECT_EQ(locus::store::migrate(db), static_cast<int>(locus::server::migrations().size()));
    SqlStore again(t.path());
    EXPECT_EQ(again.list(kind("maps"), std::nullopt, 10, 0).total, 1);
}

TEST(Store, RefusesADatabaseFromANewerVersion) {
    TempDir t{"store"};
    {
        locus::store::Db db(t.path());
        db.exec("PRAGMA user_version = 999");
    }
    EXPECT_THROW(SqlStore repo(t.path()), locus::store::DbError);
}

TEST(Store, CreateGetUpdateRemove) {
    TempDir t{"store"};
    SqlStore repo(t.path());
    const auto c = make_chain(repo);
    EXPECT_EQ(repo.get(kind("floors"), c.floor).fields.get<double>("width"), 10.0);
    repo.update(kind("floors"), c.floor, {{"width", 12.5}});
    EXPECT_EQ(repo.get(kind("floors"), c.floor).fields.get<double>("width"), 12.5);
    EXPECT_THROW(repo.create(kind("floors"), c.building, {{"name", "F"}, {"level", 1}, {"width", 1.0}, {"height", 1.0}}),
                 locus::store::Conflict);
    EXPECT_THROW(repo.create(kind("floors"), 999, {{"name", "G"}, {"level", 1}, {"width", 1.0}, {"height", 1.0}}),
                 locus::store::NotFound);
    repo.remove(kind("maps"), c.map);
    EXPECT_THROW(repo.get(kind("rps"), c.rp), locus::store::NotFound);
}

TEST(Store, MergeScansIsExactAndIdempotentPerRp) {
    TempDir t{"store"};
    SqlStore repo(t.path());
    const auto c = make_chain(repo);
    // {-60, -62} then {-64}: mean -62, population variance 8/3.
    locus::store::ScanBatch a{"u", {{"wifi", "ap", locus::RssStats{-61.0, 1.0, 2}}}, 2};
    locus::store::ScanBatch b{"v", {{"wifi", "ap", locus::RssStats{-64.0, 0.0, 1}}}, 1};
    EXPECT_TRUE(repo.merge_scans(c.rp, a).applied);
    EXPECT_FALSE(repo.merge_scans(c.rp, a).applied);
    const auto r = repo.merge_scans(c.rp, b);
    EXPECT_TRUE(r.applied);
    const auto m = r.rp.measurements.at(0);
    EXPECT_EQ(m.stats.count, 3);
    EXPECT_NEAR(m.stats.mean, -62.0, 1e-12);
    EXPECT_NEAR(m.stats.variance, 8.0 / 3.0, 1e-12);
    EXPECT_EQ(r.rp.rp.fields.get<std::int64_t>("scans"), 3);
    // The same upload id on another RP is a different upload.
    const long long rp2 = repo.create(kind("rps"), c.radiomap, {{"name", "q"}, {"x", 0.0}, {"y", 0.0}}).id;
    EXPECT_TRUE(repo.merge_scans(rp2, a).applied);
}

TEST(Store, SnapshotsForTheIndexCarryTheHierarchy) {
    TempDir t{"store"};
    SqlStore repo(t.path());
    const auto c = make_chain(repo);
    repo.merge_scans(c.rp, {std::nullopt, {{"wifi", "ap", locus::RssStats{-60.0, 1.0, 2}}}, 2});
    repo.create(kind("rooms"), c.floor, Fields({{"name", "Hall"}}, std::vector<locus::Rect>{{0, 0, 2, 3}}));
    const auto rps = repo.rps_of_map(c.map);
    ASSERT_EQ(rps.size(), 1u);
    EXPECT_EQ(rps[0].floor_id, c.floor);
    EXPECT_EQ(rps[0].building_id, c.building);
    EXPECT_EQ(rps[0].rp.scans, 2);
    ASSERT_EQ(rps[0].rp.measurements.size(), 1u);
    EXPECT_DOUBLE_EQ(rps[0].rp.measurements[0].stats.mean, -60.0);
    const auto rooms = repo.rooms_of_floor(c.floor);
    ASSERT_EQ(rooms.size(), 1u);
    EXPECT_TRUE(rooms[0].contains({1.0, 2.0}));
    EXPECT_EQ(repo.map_of_radiomap(c.radiomap), c.map);
}

TEST(Store, AFailedImportLeavesNoTrace) {
    TempDir t{"store"};
    SqlStore repo(t.path());
    const auto c = make_chain(repo);
    const locus::store::RadioMapDocument doc{{{"name", "dup"}}, {{"a", {0, 0}, 0, {}}, {"a", {1, 1}, 0, {}}}, {}};
    EXPECT_THROW(repo.import_radiomap(c.floor, doc), locus::store::Conflict);
    EXPECT_EQ(repo.list(kind("radiomaps"), c.floor, 10, 0).total, 1);
}

TEST(Store, DemoBundleImports) {
    TempDir t{"store"};
    SqlStore repo(t.path());
    EXPECT_FALSE(repo.has_maps());
    repo.import_map_bundle(locus::http::parse_map_bundle(json::parse(locus::server::demo_map_json())));
    EXPECT_TRUE(repo.has_maps());
    const auto ids = repo.radiomap_ids();
    ASSERT_EQ(ids.size(), 2u);
    EXPECT_EQ(repo.rps_of_radiomap(ids[0]).size(), 12u);
}

std::int64_t count_rows(locus::store::Db& db, const std::string& table) {
    locus::store::Stmt s(db, "SELECT COUNT(*) FROM " + table);
    s.step();
    return s.int64(0);
}

// Regression: a deleted newest row's id went to the next row, so a client holding the old
// id read another object. Every kind the API exposes: create two, delete the newer, create.
TEST(Store, AnIdIsNeverHandedOutTwice) {
    TempDir t{"store"};
    SqlStore repo(t.path());
    const auto c = make_chain(repo);
    struct Case {
        const char* kind;
        std::optional<long long> parent;
        Fields a, b;
    };
    const Fields floor_b = {{"name", "F2"}, {"level", 1}, {"width", 10.0}, {"height", 5.0}};
    const std::vector<Case> cases = {
        {"maps", std::nullopt, {{"name", "M2"}}, {{"name", "M3"}}},
        {"buildings", c.map, {{"name", "B2"}}, {{"name", "B3"}}},
        {"floors", c.building, floor_b, {{"name", "F3"}, {"level", 2}, {"width", 1.0}, {"height", 1.0}}},
        {"rooms", c.floor, {{"name", "r1"}}, {{"name", "r2"}}},
        {"pois", c.floor, {{"name", "p1"}, {"x", 1.0}, {"y", 1.0}}, {{"name", "p2"}, {"x", 2.0}, {"y", 2.0}}},
        {"radiomaps", c.floor, {{"name", "R2"}}, {{"name", "R3"}}},
        {"rps", c.radiomap, {{"name", "q1"}, {"x", 1.0}, {"y", 1.0}}, {{"name", "q2"}, {"x", 2.0}, {"y", 2.0}}},
    };
    for (const auto& k : cases) {
        SCOPED_TRACE(k.kind);
        const auto newest = repo.create(kind(k.kind), k.parent, k.a).id;
        repo.remove(kind(k.kind), newest);
        const auto next = repo.create(kind(k.kind), k.parent, k.b).id;
        EXPECT_GT(next, newest) << "id " << newest << " was reused";
        EXPECT_THROW(repo.get(kind(k.kind), newest), locus::store::NotFound);
    }
    // Also across a reopen: the high-water mark is stored, not kept in memory.
    const auto rp = repo.create(kind("rps"), c.radiomap, {{"name", "last"}, {"x", 0.0}, {"y", 0.0}}).id;
    repo.remove(kind("rps"), rp);
    SqlStore reopened(t.path());
    EXPECT_GT(reopened.create(kind("rps"), c.radiomap, {{"name", "again"}, {"x", 0.0}, {"y", 0.0}}).id, rp);
}

// A database written by schema version 1 (plain INTEGER PRIMARY KEY) moves to AUTOINCREMENT
// with every row, id and reference, and ON DELETE CASCADE still works afterwards: the rebuild
// must not cascade its own DROP TABLEs into the children.
TEST(Store, AVersion1DatabaseMigratesWithItsRowsReferencesAndCascades) {
    TempDir t{"store"};
    {
        locus::store::Db db(t.path());  // foreign keys on, as the server runs
        db.exec(locus::server::migrations().at(0));
        db.exec("PRAGMA user_version = 1");
        db.exec(R"sql(
            INSERT INTO maps (id, name) VALUES (1, 'kept'), (2, 'other');
            INSERT INTO buildings (id, map_id, name) VALUES (1, 1, 'B'), (2, 2, 'B');
            INSERT INTO floors (id, building_id, name, level, width, height) VALUES (1, 1, 'F', 0, 30, 15), (2, 2, 'F', 0, 1, 1);
            INSERT INTO rooms (id, floor_id, name) VALUES (4, 1, 'Lobby');
            INSERT INTO room_rects (room_id, xmin, ymin, xmax, ymax) VALUES (4, 0, 0, 5, 5), (4, 5, 0, 8, 2);
            INSERT INTO pois (id, floor_id, name, kind, x, y) VALUES (3, 1, 'Door', 'exit', 1, 2);
            INSERT INTO radiomaps (id, floor_id, name) VALUES (1, 1, 'R'), (2, 2, 'R');
            INSERT INTO rps (id, radiomap_id, name, x, y, scans) VALUES (25, 1, 'a', 1, 1, 3), (26, 1, 'b', 2, 2, 1), (27, 2, 'c', 0, 0, 0);
            INSERT INTO measurements (rp_id, type, bssid, mean, variance, count) VALUES
              (25, 'wifi', 'aa:bb', -50, 1, 3), (26, 'wifi', 'aa:bb', -60, 0, 1), (27, 'ble', 'cc', -70, 0, 1);
            INSERT INTO uploads (rp_id, upload_id) VALUES (25, 'u1');
        )sql");
    }
    SqlStore repo(t.path());
    {
        locus::store::Db db(t.path());
        locus::store::Stmt v(db, "PRAGMA user_version");
        v.step();
        EXPECT_EQ(v.int64(0), static_cast<std::int64_t>(locus::server::migrations().size()));
        locus::store::Stmt fk(db, "PRAGMA foreign_key_check");
        EXPECT_FALSE(fk.step()) << "dangling reference in " << fk.text(0);
        locus::store::Stmt sql(db, "SELECT sql FROM sqlite_schema WHERE name = 'rps'");
        ASSERT_TRUE(sql.step());
        EXPECT_NE(sql.text(0).find("AUTOINCREMENT"), std::string::npos) << sql.text(0);
        EXPECT_EQ(count_rows(db, "measurements"), 3);
        EXPECT_EQ(count_rows(db, "room_rects"), 2);
        EXPECT_EQ(count_rows(db, "uploads"), 1);
        EXPECT_EQ(count_rows(db, "sqlite_schema WHERE name LIKE '%_v2'"), 0);
    }
    EXPECT_EQ(repo.get(kind("maps"), 1).fields.get<std::string>("name"), "kept");
    EXPECT_EQ(repo.get(kind("floors"), 1).fields.get<double>("width"), 30.0);
    EXPECT_EQ(repo.get(kind("rooms"), 4).fields.rects.value().size(), 2u);
    EXPECT_EQ(repo.get(kind("pois"), 3).fields.get<std::string>("kind"), "exit");
    const auto rp = repo.rp_with_measurements(25);
    EXPECT_EQ(rp.rp.fields.get<std::int64_t>("scans"), 3);
    ASSERT_EQ(rp.measurements.size(), 1u);
    EXPECT_EQ(rp.measurements[0].stats.count, 3);
    // The upload ids survive: a repeated upload is still ignored.
    EXPECT_FALSE(repo.merge_scans(25, {std::string("u1"), {{"wifi", "aa:bb", locus::RssStats{-40.0, 0.0, 1}}}, 1}).applied);
    // Foreign keys are enforced again, and a delete still cascades to the bottom.
    EXPECT_THROW(repo.create(kind("rps"), 99, {{"name", "x"}, {"x", 0.0}, {"y", 0.0}}), locus::store::NotFound);
    repo.remove(kind("maps"), 2);
    EXPECT_THROW(repo.get(kind("rps"), 27), locus::store::NotFound);
    {
        locus::store::Db db(t.path());
        EXPECT_EQ(count_rows(db, "measurements"), 2);
        EXPECT_EQ(count_rows(db, "buildings"), 1);
        EXPECT_THROW(db.exec("INSERT INTO buildings (map_id, name) VALUES (42, 'orphan')"), locus::store::DbError);
    }
    // The migrated ids are the high-water mark: new rows never take an old id.
    repo.remove(kind("rps"), 26);
    EXPECT_GT(repo.create(kind("rps"), 1, {{"name", "new"}, {"x", 0.0}, {"y", 0.0}}).id, 27);
    EXPECT_GT(repo.create(kind("maps"), std::nullopt, {{"name", "new"}}).id, 2);
}

// The change feed: one typed change per committed write, with where the row sits for the
// kinds an index depends on; nothing for a refused write or a repeated upload.
TEST(Store, EveryCommittedWriteIsPublishedOnceAndARefusedOneNever) {
    TempDir t{"store"};
    SqlStore repo(t.path());
    std::vector<locus::store::Change> seen;
    const auto token = repo.subscribe([&](const locus::store::Change& c) { seen.push_back(c); });
    const auto c = make_chain(repo);
    ASSERT_EQ(seen.size(), 5u);
    EXPECT_EQ(seen[0].kind->name, "maps");
    EXPECT_EQ(seen[4].kind->name, "rps");
    EXPECT_EQ(seen[4].id, c.rp);
    EXPECT_EQ(seen[4].radiomap_id, c.radiomap);
    EXPECT_EQ(seen[4].map_id, c.map);
    EXPECT_FALSE(seen[4].deleted);
    EXPECT_EQ(seen[3].radiomap_id, c.radiomap);
    EXPECT_EQ(seen[3].map_id, c.map);
    EXPECT_FALSE(seen[0].map_id.has_value());  // only where an index needs it

    seen.clear();
    const locus::store::ScanBatch batch{"once", {{"wifi", "ap", locus::RssStats{-60.0, 0.0, 1}}}, 1};
    repo.merge_scans(c.rp, batch);
    repo.merge_scans(c.rp, batch);  // a repeat changes nothing, so it says nothing
    EXPECT_THROW(repo.create(kind("buildings"), c.map, {{"name", "B"}}), locus::store::Conflict);
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0].kind->name, "rps");
    EXPECT_EQ(seen[0].radiomap_id, c.radiomap);

    // A delete names the place the row had, read before it went.
    seen.clear();
    repo.remove(kind("radiomaps"), c.radiomap);
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_TRUE(seen[0].deleted);
    EXPECT_EQ(seen[0].map_id, c.map);

    repo.unsubscribe(token);
    repo.remove(kind("maps"), c.map);
    EXPECT_EQ(seen.size(), 1u);
}

}  // namespace
}  // namespace store_test
