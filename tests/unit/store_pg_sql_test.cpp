// The PostgreSQL side's pure parts: the store's SQL respelled for PostgreSQL, URLs without
// their passwords, and the change announcement's payload.
#include <gtest/gtest.h>

#include "store/kinds.hpp"
#include "store/pg_changes.hpp"
#include "store/pg_detail.hpp"

namespace store_pg_sql_test {
namespace {

using locus::store::pg::to_postgres;

TEST(PgSql, PlaceholdersAreNumberedAndQuotedTextIsLeftAlone) {
    EXPECT_EQ(to_postgres("SELECT a FROM t WHERE id = ? AND name = ?"), "SELECT a FROM t WHERE id = $1 AND name = $2");
    EXPECT_EQ(to_postgres("SELECT a FROM t WHERE p = ?1 LIMIT ?2 OFFSET ?3"), "SELECT a FROM t WHERE p = $1 LIMIT $2 OFFSET $3");
    EXPECT_EQ(to_postgres("SELECT 'what?', ? FROM t"), "SELECT 'what?', $1 FROM t");
    EXPECT_EQ(to_postgres("SELECT 'it''s ?', ?"), "SELECT 'it''s ?', $1");
}

TEST(PgSql, SqliteSpellingsBecomePostgresOnes) {
    EXPECT_EQ(to_postgres("INSERT OR IGNORE INTO uploads (rp_id, upload_id) VALUES (?, ?)"),
              "INSERT INTO uploads (rp_id, upload_id) VALUES ($1, $2) ON CONFLICT DO NOTHING");
    EXPECT_EQ(to_postgres("UPDATE rps SET at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now') WHERE id = ?"),
              "UPDATE rps SET at = to_char(now() AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"') WHERE id = $1");
    // xmin and xmax are PostgreSQL system columns; words that merely contain them are not.
    EXPECT_EQ(to_postgres("SELECT r.xmin, ymin, xmax, ymax, xmin_note FROM room_rects r"),
              "SELECT r.rect_xmin, ymin, rect_xmax, ymax, xmin_note FROM room_rects r");
}

TEST(PgSql, UrlsLoseTheirPasswords) {
    EXPECT_EQ(locus::store::redacted_url("postgresql://locus:s3cret@db.example:5432/locus"), "postgresql://locus@db.example:5432/locus");
    EXPECT_EQ(locus::store::redacted_url("postgres://locus@db/locus?password=s3cret&sslmode=require"),
              "postgres://locus@db/locus?password=***&sslmode=require");
    EXPECT_EQ(locus::store::redacted_url("postgresql://db:5432/locus"), "postgresql://db:5432/locus");
    // Every password parameter goes, sslpassword's too, whichever comes first.
    EXPECT_EQ(locus::store::redacted_url("postgresql://db/locus?sslpassword=k3y&password=s3cret"),
              "postgresql://db/locus?sslpassword=***&password=***");
    EXPECT_TRUE(locus::store::is_postgres_url("postgres://x/y"));
    EXPECT_FALSE(locus::store::is_postgres_url("sqlite:/tmp/x.db"));
    EXPECT_FALSE(locus::store::is_postgres_url("/tmp/postgresql://x.db"));
}

TEST(PgChanges, APayloadReadsBackAsTheChangesItCarries) {
    using locus::store::Change;
    const std::vector<Change> changes{
        Change{&locus::store::kind("rps"), 7, false, false, 3, 1},
        Change{&locus::store::kind("floors"), 2, false, true, std::nullopt, std::nullopt},
        Change{&locus::store::kind("maps"), 1, true, false, std::nullopt, 1},
        Change{&locus::store::track_kind(), 12, false, false, std::nullopt, 4}};
    const auto n = locus::store::parse_payload(locus::store::payload_of("server-a", 42, changes));
    EXPECT_EQ(n.origin, "server-a");
    EXPECT_EQ(n.version, 42);
    EXPECT_FALSE(n.everything);
    ASSERT_EQ(n.changes.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(n.changes[i].kind, changes[i].kind);
        EXPECT_EQ(n.changes[i].id, changes[i].id);
        EXPECT_EQ(n.changes[i].deleted, changes[i].deleted);
        EXPECT_EQ(n.changes[i].plan, changes[i].plan);
        EXPECT_EQ(n.changes[i].radiomap_id, changes[i].radiomap_id);
        EXPECT_EQ(n.changes[i].map_id, changes[i].map_id);
    }
}

// Live tracks announce their writes on the feed without being a resource of the hierarchy, and
// tracks::Service sends at most 50 track changes per notification: they fit in one payload.
TEST(PgChanges, TrackChangesAreNoCrudKindAndFiftyFitOnePayload) {
    EXPECT_EQ(locus::store::find_kind("tracks"), nullptr);
    EXPECT_EQ(locus::store::track_kind().name, "tracks");
    using locus::store::Change;
    const std::vector<Change> fifty(50, Change{&locus::store::track_kind(), 9'007'199'254'740'991, false, false, std::nullopt,
                                               9'007'199'254'740'991});
    const auto n = locus::store::parse_payload(locus::store::payload_of("12345-1234567890123456789", 9'007'199'254'740'991, fifty));
    EXPECT_FALSE(n.everything);
    ASSERT_EQ(n.changes.size(), 50u);
    EXPECT_EQ(n.changes[49].kind, &locus::store::track_kind());
}

TEST(PgChanges, ThePayloadIsItsHeadThenTheVersion) {
    // The writing transaction appends the version in SQL to the head it is sent.
    using locus::store::Change;
    const std::vector<Change> changes{Change{&locus::store::kind("rps"), 7, false, false, 3, 1}};
    for (const std::int64_t v : {std::int64_t{1}, std::int64_t{42}, std::int64_t{9223372036854775807}}) {
        const std::string payload = locus::store::payload_of("server-a", v, changes);
        EXPECT_EQ(payload, locus::store::payload_head("server-a", changes) + std::to_string(v) + "}");
        EXPECT_EQ(locus::store::parse_payload(payload).version, v);
    }
}

TEST(PgChanges, ATooLongPayloadSaysEverythingChanged) {
    using locus::store::Change;
    const std::vector<Change> many(2000, Change{&locus::store::kind("rps"), 123456, false, false, 99, 98});
    const std::string payload = locus::store::payload_of("server-a", 5, many);
    EXPECT_LT(payload.size(), 8000u);  // PostgreSQL refuses a NOTIFY payload of 8000 bytes
    const auto n = locus::store::parse_payload(payload);
    EXPECT_TRUE(n.everything);
    EXPECT_EQ(n.version, 5);
    EXPECT_TRUE(n.changes.empty());
}

}  // namespace
}  // namespace store_pg_sql_test
