// The PostgreSQL connection's prepared-statement cache (pg::Prepared): a statement the server
// no longer holds, or whose plan went stale, is prepared again instead of failing for the
// connection's life; the cache is bounded without eviction. Runs only under
// scripts/with_postgres.sh.
#include <gtest/gtest.h>

#include <string>

#include "store/db.hpp"
#include "store/pg_detail.hpp"
#include "test_database.hpp"

namespace store_pg_statement_cache_test {
namespace {

using locus::store::Db;
using locus::store::DbError;
using locus::store::Stmt;
using locus::store::Transaction;

#define REQUIRE_POSTGRES()                                                                                   \
    if (!locus::testing::on_postgres())                                                                      \
    GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)"

std::int64_t count_of(Db& db, const std::string& sql) {
    Stmt s(db, sql);
    EXPECT_TRUE(s.step());
    return s.int64(0);
}

// What the session holds prepared, read without preparing anything (Db::exec is not cached).
std::int64_t prepared_on_server(Db& db) {
    db.exec("CREATE TEMP TABLE IF NOT EXISTS held (n BIGINT); DELETE FROM held; "
            "INSERT INTO held SELECT COUNT(*) FROM pg_prepared_statements");
    Stmt s(db, "SELECT n FROM held");  // prepared after the count was taken (when the cache has room)
    EXPECT_TRUE(s.step());
    return s.int64(0);
}

TEST(PostgresStatementCache, AStatementDiscardedOnTheServerIsPreparedAgain) {
    REQUIRE_POSTGRES();
    locus::testing::TestDatabase tdb;
    Db db(tdb.url());
    db.exec("CREATE TABLE t (v BIGINT); INSERT INTO t VALUES (1), (2)");
    const std::string sql = "SELECT COUNT(*) FROM t WHERE v > ?";
    auto count = [&db, &sql] {
        Stmt s(db, sql);
        s.bind(1, 0);
        EXPECT_TRUE(s.step());
        return s.int64(0);
    };
    ASSERT_EQ(count(), 2);
    for (const char* drop : {"DISCARD ALL", "DEALLOCATE ALL"}) {
        SCOPED_TRACE(drop);
        db.exec(drop);  // what a transaction-pooling PgBouncer's server reset does, among others
        EXPECT_EQ(count(), 2);
        EXPECT_EQ(count(), 2);  // and prepared from then on: no retry needed
    }

    // Inside a transaction the statement fails (the transaction is aborted anyway), and the
    // cache is emptied: the next run outside it succeeds.
    db.exec("DISCARD ALL");
    {
        Transaction tx(db);
        EXPECT_THROW(count(), DbError);
    }
    EXPECT_EQ(count(), 2);
    EXPECT_EQ(prepared_on_server(db), 1);  // the count alone: nothing stale left
}

TEST(PostgresStatementCache, AStatementWhoseResultTypeChangedIsPreparedAgain) {
    REQUIRE_POSTGRES();
    locus::testing::TestDatabase tdb;
    Db db(tdb.url());
    db.exec("CREATE TABLE t (a BIGINT); INSERT INTO t VALUES (7)");
    {
        Stmt s(db, "SELECT * FROM t");
        ASSERT_TRUE(s.step());
        EXPECT_EQ(s.column_count(), 1);
    }
    db.exec("ALTER TABLE t ADD COLUMN b BIGINT DEFAULT 8");  // "cached plan must not change result type" (0A000)
    Stmt s(db, "SELECT * FROM t");
    ASSERT_TRUE(s.step());
    EXPECT_EQ(s.column_count(), 2);
    EXPECT_EQ(s.int64(0), 7);
    EXPECT_EQ(s.int64(1), 8);
    // The stale statement was deallocated, not left in the session.
    EXPECT_EQ(prepared_on_server(db), 1);
}

TEST(PostgresStatementCache, TextsBeyondTheBoundRunUnpreparedAndNothingIsEvicted) {
    REQUIRE_POSTGRES();
    locus::testing::TestDatabase tdb;
    Db db(tdb.url());
    const auto bound = static_cast<int>(locus::store::pg::Prepared{}.limit);
    auto run = [&db](int i) {
        const auto before = db.pg_round_trips();
        EXPECT_EQ(count_of(db, "SELECT " + std::to_string(i) + " + 0"), i);
        return db.pg_round_trips() - before;
    };
    for (int i = 0; i < bound; ++i) ASSERT_EQ(run(i), 2) << "text " << i << ": prepared, then run";
    EXPECT_EQ(run(bound), 1) << "beyond the bound: run unprepared";
    EXPECT_EQ(run(bound), 1);
    EXPECT_EQ(run(0), 1) << "the first text is still prepared";
    EXPECT_EQ(run(bound - 1), 1) << "and the last one kept";
    EXPECT_EQ(prepared_on_server(db), bound);
}

}  // namespace
}  // namespace store_pg_statement_cache_test
