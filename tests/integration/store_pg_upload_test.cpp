// A scan upload on PostgreSQL stores what it stores on SQLite, bit for bit (the merge is the
// core's RssStats::merge on both), answers the same, and costs a handful of round trips
// whatever the number of APs. Runs only under scripts/with_postgres.sh.
#include <gtest/gtest.h>
#include <libpq-fe.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "locus/rss_stats.hpp"
#include "store/sql_store.hpp"
#include "temp_dir.hpp"
#include "test_database.hpp"

namespace store_pg_upload_test {
namespace {

using locus::RssStats;
using locus::store::kind;
using locus::Measurement;
using locus::store::ScanBatch;
using locus::store::SqlStore;

#define REQUIRE_POSTGRES()                                                                                   \
    if (!locus::testing::on_postgres())                                                                      \
    GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)"

struct Rps {
    long long a, b;
};

Rps make_rps(SqlStore& s) {
    const auto map = s.create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
    const auto building = s.create(kind("buildings"), map, {{"name", "B"}}).id;
    const auto floor = s.create(kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 10.0}, {"height", 5.0}}).id;
    const auto radiomap = s.create(kind("radiomaps"), floor, {{"name", "R"}}).id;
    return {s.create(kind("rps"), radiomap, {{"name", "a"}, {"x", 1.0}, {"y", 2.0}}).id,
            s.create(kind("rps"), radiomap, {{"name", "b"}, {"x", 3.0}, {"y", 2.0}}).id};
}

Measurement ap(const std::string& bssid, double mean, double variance, std::int64_t count, const char* type = "wifi") {
    return {type, locus::Bssid::stored(bssid), RssStats{mean, variance, count}};
}

// Uploads whose means and variances are not small integers, so that any other order or
// formula of the merge would show in the last bits.
std::vector<std::pair<long long, ScanBatch>> uploads(const Rps& rp) {
    std::vector<std::pair<long long, ScanBatch>> out;
    for (int i = 0; i < 12; ++i) {
        ScanBatch b;
        b.upload_id = "u" + std::to_string(i);
        b.scans = 1 + i % 3;
        b.measurements.push_back(ap("aa:00:00:00:00:01", -40.0 - 0.37 * i - 1.0 / (i + 3), 0.1 * i + 1.0 / 7, 1 + i % 3));
        b.measurements.push_back(ap("aa:00:00:00:00:02", -71.3 + std::sqrt(i + 2.0), 2.0 / (i + 1), 2 + i % 5));
        if (i >= 5) b.measurements.push_back(ap("aa:00:00:00:00:0" + std::to_string(3 + i % 2), -80.0 + i / 3.0, 0.0, 1));
        if (i % 4 == 0) b.measurements.push_back(ap("0123456789abcdef", -90.5 + i, 1.5, 3, "ble"));
        out.emplace_back(i % 3 == 2 ? rp.b : rp.a, std::move(b));
        if (i == 7) out.push_back(out[3]);  // a retried upload: acknowledged, not applied
    }
    ScanBatch no_id;  // an upload without an id is always applied
    no_id.scans = 2;
    no_id.measurements.push_back(ap("aa:00:00:00:00:01", -50.25, 3.0, 2));
    out.emplace_back(rp.a, no_id);
    out.emplace_back(rp.a, no_id);
    return out;
}

void expect_same(const locus::store::RpRecord& pg, const locus::store::RpRecord& lite, const std::string& what) {
    SCOPED_TRACE(what);
    EXPECT_EQ(pg.rp.id, lite.rp.id);
    EXPECT_EQ(pg.rp.fields.get<std::int64_t>("scans"), lite.rp.fields.get<std::int64_t>("scans"));
    EXPECT_EQ(pg.rp.fields.get<std::string>("name"), lite.rp.fields.get<std::string>("name"));
    ASSERT_EQ(pg.measurements.size(), lite.measurements.size());
    for (std::size_t i = 0; i < pg.measurements.size(); ++i) {
        const auto &p = pg.measurements[i], &l = lite.measurements[i];
        EXPECT_EQ(p.type, l.type);
        EXPECT_EQ(p.bssid.str(), l.bssid.str());
        EXPECT_EQ(p.stats.count, l.stats.count);
        // The same double: both stores ran the same merge on the same doubles.
        EXPECT_EQ(p.stats.mean, l.stats.mean) << p.bssid.str();
        EXPECT_EQ(p.stats.variance, l.stats.variance) << p.bssid.str();
    }
}

TEST(PostgresUpload, StoresAndAnswersWhatSqliteAndTheCoreMergeGive) {
    REQUIRE_POSTGRES();
    locus::testing::TestDatabase db;
    locus::testing::TempDir dir{"pg-upload"};
    SqlStore pg(db.url());
    SqlStore lite(dir.path());
    const Rps rp = make_rps(pg);
    ASSERT_EQ(make_rps(lite).a, rp.a);

    // What the core's merge gives, applied one upload after another.
    std::map<std::pair<long long, std::string>, RssStats> expected;
    std::map<long long, std::int64_t> scans;
    std::map<std::pair<long long, std::string>, bool> seen;
    for (const auto& [rp_id, batch] : uploads(rp)) {
        const auto on_pg = pg.merge_scans(rp_id, batch);
        const auto on_lite = lite.merge_scans(rp_id, batch);
        const bool fresh = !batch.upload_id || !seen[{rp_id, *batch.upload_id}];
        if (batch.upload_id) seen[{rp_id, *batch.upload_id}] = true;
        EXPECT_EQ(on_pg.applied, fresh);
        EXPECT_EQ(on_lite.applied, fresh);
        expect_same(on_pg.rp, on_lite.rp, "the answer to " + batch.upload_id.value_or("an upload without id"));
        if (!fresh) continue;
        scans[rp_id] += batch.scans;
        for (const auto& m : batch.measurements) expected[{rp_id, m.type + "/" + m.bssid.str()}].merge(m.stats);
    }
    for (const long long id : {rp.a, rp.b}) {
        const auto stored = pg.rp_with_measurements(id);
        expect_same(stored, lite.rp_with_measurements(id), "RP " + std::to_string(id) + " as stored");
        EXPECT_EQ(stored.rp.fields.get<std::int64_t>("scans"), scans[id]);
        EXPECT_FALSE(stored.rp.fields.get<std::string>("last_upload_at").empty());
        std::size_t aps = 0;
        for (const auto& [key, want] : expected) aps += key.first == id ? 1 : 0;
        EXPECT_EQ(stored.measurements.size(), aps);
        for (const auto& m : stored.measurements) {
            const auto& want = expected.at({id, m.type + "/" + m.bssid.str()});
            EXPECT_EQ(m.stats.count, want.count);
            EXPECT_NEAR(m.stats.mean, want.mean, 1e-12);
            EXPECT_NEAR(m.stats.variance, want.variance, 1e-12);
        }
    }
}

TEST(PostgresUpload, RefusalsWriteNothingAndKeepNoUploadId) {
    REQUIRE_POSTGRES();
    locus::testing::TestDatabase db;
    SqlStore pg(db.url());
    const Rps rp = make_rps(pg);
    ScanBatch first{"first", {ap("aa:00:00:00:00:01", -50.0, 1.0, 2)}, 2};
    ASSERT_TRUE(pg.merge_scans(rp.a, first).applied);
    const auto before = pg.rp_with_measurements(rp.a);

    EXPECT_THROW(pg.merge_scans(rp.b + 100, first), locus::store::NotFound);
    // The second AP's count would pass 2^53: the first AP, merged before the check, is not kept.
    ScanBatch too_many{"too-many", {ap("aa:00:00:00:00:02", -60.0, 0.0, 1), ap("aa:00:00:00:00:01", -50.0, 0.0, locus::kMaxCount)}, 1};
    EXPECT_THROW(pg.merge_scans(rp.a, too_many), locus::store::OutOfRange);
    ScanBatch too_many_scans{"scans", {ap("aa:00:00:00:00:02", -60.0, 0.0, 1)}, locus::kMaxCount};
    EXPECT_THROW(pg.merge_scans(rp.a, too_many_scans), locus::store::OutOfRange);

    expect_same(pg.rp_with_measurements(rp.a), before, "after the refusals");
    // A refused upload's id was not kept: sent again within bounds, it applies.
    too_many.measurements.pop_back();
    EXPECT_TRUE(pg.merge_scans(rp.a, too_many).applied);
}

TEST(PostgresUpload, AnUploadCostsFourRoundTripsWhateverItsApsAndARetryThree) {
    REQUIRE_POSTGRES();
    locus::testing::TestDatabase db;
    SqlStore pg(db.url());
    const Rps rp = make_rps(pg);
    // The first upload and retry also prepare their statements on the connection (once each).
    ScanBatch warm{"warm", {ap("cc:00:00:00:00:01", -60.0, 0.5, 1)}, 1};
    ASSERT_TRUE(pg.merge_scans(rp.b, warm).applied);
    ASSERT_FALSE(pg.merge_scans(rp.b, warm).applied);
    for (const int aps : {1, 2, 20}) {
        ScanBatch b{"n" + std::to_string(aps), {}, 1};
        for (int i = 0; i < aps; ++i) b.measurements.push_back(ap("cc:00:00:00:00:" + std::to_string(10 + i), -60.0 - i, 0.5, 1));
        auto at = pg.round_trips();
        ASSERT_TRUE(pg.merge_scans(rp.a, b).applied);
        EXPECT_EQ(pg.round_trips() - at, 4) << aps << " APs";
        at = pg.round_trips();
        ASSERT_FALSE(pg.merge_scans(rp.a, b).applied);
        EXPECT_EQ(pg.round_trips() - at, 3) << "a retry of " << aps << " APs";
    }
}

TEST(PostgresUpload, AStatementSentWithBeginOrCommitThatFailsLeavesNothingOpenOrWritten) {
    REQUIRE_POSTGRES();
    locus::testing::TestDatabase tdb;
    locus::store::Db db(tdb.url());
    db.exec("CREATE TABLE t (v BIGINT)");
    // Sent with BEGIN: the transaction it opened is rolled back before the constructor throws.
    EXPECT_THROW(locus::store::Transaction(db, locus::store::Transaction::Mode::write, "SELECT 1 / 0"), locus::store::DbError);
    // The session's own state, not the Db's flag (never set when the constructor throws).
    EXPECT_EQ(PQtransactionStatus(db.pg()), PQTRANS_IDLE);
    {
        // Sent with COMMIT: nothing of the transaction is kept.
        locus::store::Transaction tx(db);
        locus::store::Stmt(db, "INSERT INTO t (v) VALUES (1)").run();
        EXPECT_THROW(tx.commit("SELECT 1 / 0"), locus::store::DbError);
    }
    {
        // The connection works on: a transaction with both, and its statements, go through.
        locus::store::Transaction tx(db, locus::store::Transaction::Mode::write, "SELECT pg_advisory_xact_lock(1)");
        locus::store::Stmt(db, "INSERT INTO t (v) VALUES (2)").run();
        tx.commit("SELECT 1");
    }
    locus::store::Stmt sum(db, "SELECT COUNT(*), COALESCE(SUM(v), 0) FROM t");
    ASSERT_TRUE(sum.step());
    EXPECT_EQ(sum.int64(0), 1);
    EXPECT_EQ(sum.int64(1), 2);
}

TEST(PostgresUpload, ACommitAfterASwallowedFailureThrowsAndWritesNothing) {
    REQUIRE_POSTGRES();
    locus::testing::TestDatabase tdb;
    locus::store::Db db(tdb.url());
    db.exec("CREATE TABLE t (v BIGINT)");
    for (const char* last : {"", "SELECT 1"}) {
        SCOPED_TRACE(std::string("commit(\"") + last + "\")");
        {
            locus::store::Transaction tx(db);
            locus::store::Stmt(db, "INSERT INTO t (v) VALUES (1)").run();
            try {
                locus::store::Stmt(db, "SELECT 1 / 0").run();
                ADD_FAILURE() << "division by zero ran";
            } catch (const locus::store::DbError&) {
                // Swallowed: the transaction is aborted all the same.
            }
            EXPECT_THROW(tx.commit(last), locus::store::DbError);
        }
        EXPECT_EQ(PQtransactionStatus(db.pg()), PQTRANS_IDLE);
    }
    locus::store::Stmt rows(db, "SELECT COUNT(*) FROM t");
    ASSERT_TRUE(rows.step());
    EXPECT_EQ(rows.int64(0), 0);
}

}  // namespace
}  // namespace store_pg_upload_test
