// The SQLite repository on a real file: migrations, CRUD, merge, cascade, snapshots.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "store/migrations.hpp"
#include "store/repository.hpp"

using locus::store::Repository;
using locus::store::kind;
using nlohmann::json;

namespace {
struct TempDb {
    std::filesystem::path dir;
    TempDb() {
        std::string tmpl = (std::filesystem::temp_directory_path() / "locus-store-XXXXXX").string();
        dir = mkdtemp(tmpl.data());
    }
    ~TempDb() { std::filesystem::remove_all(dir); }
    std::string path() const { return (dir / "t.db").string(); }
};

struct Chain {
    long long map, building, floor, radiomap, rp;
};

Chain make_chain(Repository& repo) {
    Chain c{};
    c.map = repo.create(kind("maps"), std::nullopt, {{"name", "M"}}).at("id");
    c.building = repo.create(kind("buildings"), c.map, {{"name", "B"}}).at("id");
    c.floor = repo.create(kind("floors"), c.building, {{"name", "F"}, {"level", 0}, {"width", 10.0}, {"height", 5.0}}).at("id");
    c.radiomap = repo.create(kind("radiomaps"), c.floor, {{"name", "R"}}).at("id");
    c.rp = repo.create(kind("rps"), c.radiomap, {{"name", "p"}, {"x", 1.0}, {"y", 2.0}}).at("id");
    return c;
}
}  // namespace

TEST(Store, MigratesToTheLatestVersionOnceAndKeepsData) {
    TempDb t;
    {
        Repository repo(t.path());
        repo.create(kind("maps"), std::nullopt, {{"name", "kept"}});
    }
    locus::store::Db db(t.path());
    EXPECT_EQ(locus::store::migrate(db), static_cast<int>(locus::server::migrations().size()));
    Repository again(t.path());
    EXPECT_EQ(again.list(kind("maps"), std::nullopt, 10, 0).at("total"), 1);
}

TEST(Store, RefusesADatabaseFromANewerVersion) {
    TempDb t;
    {
        locus::store::Db db(t.path());
        db.exec("PRAGMA user_version = 999");
    }
    EXPECT_THROW(Repository repo(t.path()), locus::store::SqliteError);
}

TEST(Store, CreateGetUpdateRemove) {
    TempDb t;
    Repository repo(t.path());
    const auto c = make_chain(repo);
    EXPECT_EQ(repo.get(kind("floors"), c.floor).at("width"), 10.0);
    repo.update(kind("floors"), c.floor, {{"width", 12.5}});
    EXPECT_EQ(repo.get(kind("floors"), c.floor).at("width"), 12.5);
    EXPECT_THROW(repo.create(kind("floors"), c.building, {{"name", "F"}, {"level", 1}, {"width", 1.0}, {"height", 1.0}}),
                 locus::store::Conflict);
    EXPECT_THROW(repo.create(kind("floors"), 999, {{"name", "G"}, {"level", 1}, {"width", 1.0}, {"height", 1.0}}),
                 locus::store::NotFound);
    repo.remove(kind("maps"), c.map);
    EXPECT_THROW(repo.get(kind("rps"), c.rp), locus::store::NotFound);
}

TEST(Store, MergeScansIsExactAndIdempotentPerRp) {
    TempDb t;
    Repository repo(t.path());
    const auto c = make_chain(repo);
    // {-60, -62} then {-64}: mean -62, population variance 8/3.
    locus::store::ScanUpload a{"u", {{"wifi", "ap", locus::RssStats{-61.0, 1.0, 2}}}, 2};
    locus::store::ScanUpload b{"v", {{"wifi", "ap", locus::RssStats{-64.0, 0.0, 1}}}, 1};
    EXPECT_TRUE(repo.merge_scans(c.rp, a).applied);
    EXPECT_FALSE(repo.merge_scans(c.rp, a).applied);
    const auto r = repo.merge_scans(c.rp, b);
    EXPECT_TRUE(r.applied);
    const auto m = r.rp.at("measurements").at(0);
    EXPECT_EQ(m.at("count"), 3);
    EXPECT_NEAR(m.at("mean").get<double>(), -62.0, 1e-12);
    EXPECT_NEAR(m.at("variance").get<double>(), 8.0 / 3.0, 1e-12);
    EXPECT_EQ(r.rp.at("scans"), 3);
    // The same upload id on another RP is a different upload.
    const long long rp2 = repo.create(kind("rps"), c.radiomap, {{"name", "q"}, {"x", 0.0}, {"y", 0.0}}).at("id");
    EXPECT_TRUE(repo.merge_scans(rp2, a).applied);
}

TEST(Store, SnapshotsForTheIndexCarryTheHierarchy) {
    TempDb t;
    Repository repo(t.path());
    const auto c = make_chain(repo);
    repo.merge_scans(c.rp, {std::nullopt, {{"wifi", "ap", locus::RssStats{-60.0, 1.0, 2}}}, 2});
    repo.create(kind("rooms"), c.floor, {{"name", "Hall"}, {"rects", {{{"xmin", 0}, {"ymin", 0}, {"xmax", 2}, {"ymax", 3}}}}});
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
    TempDb t;
    Repository repo(t.path());
    const auto c = make_chain(repo);
    const json doc = {{"name", "dup"}, {"rps", {{{"name", "a"}, {"x", 0}, {"y", 0}}, {{"name", "a"}, {"x", 1}, {"y", 1}}}}};
    EXPECT_THROW(repo.import_radiomap(c.floor, doc), locus::store::Conflict);
    EXPECT_EQ(repo.list(kind("radiomaps"), c.floor, 10, 0).at("total"), 1);
}

TEST(Store, DemoBundleImports) {
    TempDb t;
    Repository repo(t.path());
    EXPECT_FALSE(repo.has_maps());
    repo.import_map_bundle(json::parse(locus::server::demo_map_json()));
    EXPECT_TRUE(repo.has_maps());
    const auto ids = repo.radiomap_ids();
    ASSERT_EQ(ids.size(), 2u);
    EXPECT_EQ(repo.rps_of_radiomap(ids[0]).size(), 12u);
}
