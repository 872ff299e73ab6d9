#pragma once
// The PostgreSQL side of db.hpp's Db and Stmt, over libpq. Only db.cpp and the change
// listener use it; everything else goes through Db.
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <cstdint>
#include <vector>

#include "store/db.hpp"

namespace locus::store::pg {

// The store's SQLite-flavoured SQL in PostgreSQL's spelling: ?N and ? become $N, INSERT OR
// IGNORE becomes INSERT … ON CONFLICT DO NOTHING, strftime('…', 'now') the same UTC text
// from now(), and the columns xmin, xmax (system columns in PostgreSQL) rect_xmin, rect_xmax.
// Quoted text is left alone.
std::string to_postgres(std::string_view sql);

// Connects; throws DbError(SQLITE_CANTOPEN) naming the URL without its password.
pg_conn* connect(const std::string& url);
void close(pg_conn* c);
// Runs one or more statements without parameters; throws DbError. Answers the last one's
// command status ("COMMIT", or "ROLLBACK" for a COMMIT of an aborted transaction).
std::string exec(pg_conn* c, std::string_view sql);
// The statements a connection has prepared (by their text and parameter count): PostgreSQL
// parses and plans a statement once per connection instead of at every run. Emptied when the
// connection is reset (its prepared statements go with the session), and when the server says
// a cached statement is gone or stale (run() then retries once outside a transaction).
//
// At most `limit` texts are prepared; a text met once the cache is full runs unprepared
// (PQexecParams: one round trip, as before any caching) and nothing is evicted. An LRU was the
// other choice, and is worse here: the store's fixed texts are a few dozen and prepared at their
// first run; only PATCH's UPDATE, whose SET list is the fields sent, makes more, and those are
// rare. Evicting would cost a DEALLOCATE round trip on every miss once full, and a working set
// above the bound would thrash (prepare, deallocate, run: three round trips where one does).
// Not preparing is never slower than no cache at all.
struct Prepared {
    std::unordered_map<std::string, std::string> names;
    std::size_t next = 0;
    std::size_t limit = 512;
    // The cache was emptied while the session may still hold some of its statements: they are
    // deallocated before the next statement run outside a transaction.
    bool stale_on_server = false;
};
// Runs one statement (already in PostgreSQL's spelling); throws DbError on failure. With
// `prepared`, the statement is prepared on its first run (one more round trip, counted in
// `*round_trips`) and run prepared from then on.
pg_result* run(pg_conn* c, const std::string& sql, const std::vector<std::optional<std::string>>& params,
               const std::vector<int>& formats, Prepared* prepared = nullptr, std::int64_t* round_trips = nullptr);
void clear(pg_result* r);
int row_count(const pg_result* r);
int column_count(const pg_result* r);
bool is_null(const pg_result* r, int row, int col);
const char* value(const pg_result* r, int row, int col);
std::string column_name(const pg_result* r, int col);
// SQLITE_INTEGER, SQLITE_FLOAT, SQLITE_TEXT or SQLITE_BLOB for the column's type.
int column_type(const pg_result* r, int col);
bool is_bytea(const pg_result* r, int col);
// A bytea value in text form (\x…) as its bytes.
std::string unescape_bytea(const char* text);
// `text` as a quoted SQL literal for this connection (PQescapeLiteral); throws DbError.
std::string literal(pg_conn* c, std::string_view text);
// The rows an INSERT, UPDATE or DELETE changed.
int changed_rows(pg_result* r);
// The DbError a failed statement, or a lost connection, stands for.
DbError error_of(pg_conn* c, pg_result* r, std::string_view context);

}  // namespace locus::store::pg
