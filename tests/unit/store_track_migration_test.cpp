// Migration 013 rebuilds the tracks table (SQLite cannot alter its fusion CHECK): a version-12
// database's tracks keep their ids, fusion, fixes and shares, the largest id ever handed out
// stays the high-water mark, foreign keys still cascade, and the new methods are accepted.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "store/db.hpp"
#include "store/migrations.hpp"
#include "temp_dir.hpp"

namespace store_track_migration_test {
namespace {

using locus::testing::TempDir;

std::int64_t scalar(locus::store::Db& db, const std::string& sql) {
    locus::store::Stmt q(db, sql);
    EXPECT_TRUE(q.step()) << sql;
    return q.int64(0);
}

TEST(StoreTrackMigration, Version12TracksKeepTheirRowsIdsAndReferences) {
    TempDir t{"trackmig"};
    const auto& all = locus::server::migrations();
    ASSERT_GE(all.size(), 13u);
    locus::store::Db db(t.path());  // foreign keys on, as the server runs
    for (std::size_t i = 0; i < 12; ++i) db.exec(all[i]);
    db.exec("PRAGMA user_version = 12");
    db.exec(R"sql(
        INSERT INTO maps (id, name) VALUES (1, 'M');
        INSERT INTO tracks (id, map_id, label, token_hash, state, created_at, last_fix_at, fusion)
          VALUES (1, 1, 'a', x'01', 'live', 1, 2, 'particle'), (3, 1, NULL, x'03', 'closed', 1, 2, 'walk_pf'),
                 (7, 1, 'gone soon', x'07', 'live', 1, 2, 'walk_pf');
        INSERT INTO track_fixes (track_id, t, floor_id, x, y, accuracy_m) VALUES (1, 10, 5, 1, 2, 3), (3, 11, 5, 4, 5, 6);
        INSERT INTO track_shares (track_id, token_hash, created_at) VALUES (1, x'aa', 1);
        DELETE FROM tracks WHERE id = 7;
    )sql");
    ASSERT_EQ(locus::store::migrate(db), static_cast<int>(all.size()));
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM tracks"), 2);
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM tracks WHERE id = 1 AND fusion = 'particle' AND fusion_options IS NULL"), 1);
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM tracks WHERE id = 3 AND fusion = 'walk_pf' AND state = 'closed'"), 1);
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM track_fixes"), 2);
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM track_shares"), 1);
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM sqlite_schema WHERE name LIKE 'tracks_v13%'"), 0);
    {
        locus::store::Stmt fk(db, "PRAGMA foreign_key_check");
        EXPECT_FALSE(fk.step()) << "dangling reference in " << fk.text(0);
    }
    // Deleted track 7's id is never handed out again.
    db.exec("INSERT INTO tracks (map_id, token_hash, state, created_at, last_fix_at, fusion, fusion_options) "
            "VALUES (1, x'08', 'live', 1, 1, 'kalman_ranging', '{\"r_scale\":2.0}')");
    EXPECT_EQ(db.last_insert_id(), 8);
    // kalman_trilateration is stored under its first name (tracks/fusion_method.hpp).
    db.exec("INSERT INTO tracks (map_id, token_hash, state, created_at, last_fix_at, fusion) VALUES (1, x'09', 'live', 1, 1, 'kalman_seed')");
    db.exec("INSERT INTO tracks (map_id, token_hash, state, created_at, last_fix_at, fusion, fusion_options) "
            "VALUES (1, x'0b', 'live', 1, 1, 'ekf_ranging', '{\"reading_sigma_db\":5.0}')");
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM tracks WHERE fusion = 'ekf_ranging'"), 1);
    EXPECT_THROW(db.exec("INSERT INTO tracks (map_id, token_hash, state, created_at, last_fix_at, fusion) "
                         "VALUES (1, x'0a', 'live', 1, 1, 'kalman')"),
                 locus::store::DbError);
    // The children still point at tracks, and a delete still cascades.
    db.exec("DELETE FROM tracks WHERE id = 1");
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM track_fixes"), 1);
    EXPECT_EQ(scalar(db, "SELECT count(*) FROM track_shares"), 0);
    EXPECT_THROW(db.exec("INSERT INTO track_fixes (track_id, t, floor_id, x, y, accuracy_m) VALUES (42, 1, 1, 0, 0, 0)"),
                 locus::store::DbError);
}

}  // namespace
}  // namespace store_track_migration_test
