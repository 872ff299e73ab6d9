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
// Runs one or more statements without parameters; throws DbError.
void exec(pg_conn* c, std::string_view sql);
// The statements a connection has prepared (by their text and parameter count): PostgreSQL
// parses and plans a statement once per connection instead of at every run. Emptied when the
// connection is reset (its prepared statements go with the session).
struct Prepared {
    std::unordered_map<std::string, std::string> names;
    std::size_t next = 0;
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
