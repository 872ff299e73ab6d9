#pragma once
// Thin RAII layer over a SQL connection: prepared statements, transactions. The embedded engine
// is SQLite (its C API); a postgresql:// URL opens PostgreSQL over libpq instead (db_pg.cpp),
// behind the same calls: the store's SQL is written once, in the common subset of both
// dialects, and pg_sql.hpp rewrites the few SQLite spellings it uses. PostgreSQL's errors are
// reported as DbError with the SQLite code of the same meaning (a unique violation is
// SQLITE_CONSTRAINT_UNIQUE, a lost connection SQLITE_IOERR), so the callers' handling holds.
#include <sqlite3.h>

#include <vector>

#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <concepts>
#include <memory>

struct pg_conn;
struct pg_result;

namespace locus::store {
namespace pg {
struct Prepared;
}

struct DbError : std::runtime_error {
    int code;
    std::string file;  // the database file, when the error is about it (empty otherwise)
    DbError(int c, const std::string& what, std::string db_file = {})
        : std::runtime_error(what), code(c), file(std::move(db_file)) {}
    bool is_constraint() const { return (code & 0xff) == SQLITE_CONSTRAINT; }
    bool is_unique() const { return code == SQLITE_CONSTRAINT_UNIQUE || code == SQLITE_CONSTRAINT_PRIMARYKEY; }
    // The database, not the request, is at fault: a full disk, an I/O error, a read-only,
    // unopenable or corrupt file, or the write lock still held elsewhere after the busy
    // timeout. The same request may succeed later (the HTTP layer answers 503).
    bool is_storage_fault() const {
        switch (code & 0xff) {
            case SQLITE_FULL:
            case SQLITE_IOERR:
            case SQLITE_READONLY:
            case SQLITE_CANTOPEN:
            case SQLITE_CORRUPT:
            case SQLITE_NOTADB:
            case SQLITE_BUSY:
                return true;
            default:
                return false;
        }
    }
};

class Db;

// True for a postgresql:// or postgres:// URL.
bool is_postgres_url(std::string_view url);
// The URL without its password, for logs and messages.
std::string redacted_url(std::string_view url);

class Stmt {
public:
    Stmt(Db& db, std::string_view sql);
    ~Stmt();
    Stmt(const Stmt&) = delete;
    Stmt& operator=(const Stmt&) = delete;
    Stmt(Stmt&& other) noexcept;

    // Every integer type binds as a 64-bit integer (int64_t is long here, ids are long long).
    template <std::integral T>
    Stmt& bind(int i, T v) { return bind_int64(i, static_cast<std::int64_t>(v)); }
    Stmt& bind_int64(int i, std::int64_t v);
    Stmt& bind(int i, double v);
    Stmt& bind(int i, std::string_view v);
    Stmt& bind_null(int i);
    // The bytes must stay valid until the statement is stepped (they are not copied).
    Stmt& bind_blob(int i, std::string_view bytes);

    bool step();  // true while a row is available
    void run();   // steps a statement that returns no rows
    void reset();

    std::int64_t int64(int col) const;
    double real(int col) const;
    std::string text(int col) const;
    std::string blob(int col) const;
    bool is_null(int col) const;
    int column_count() const;
    int column_type(int col) const;
    std::string column_name(int col) const;

private:
    // PostgreSQL: the statement runs when first stepped, with the parameters bound so far.
    void pg_execute();
    const char* pg_value(int col) const;

    sqlite3* db_;
    sqlite3_stmt* stmt_ = nullptr;
    Db* owner_ = nullptr;
    bool pg_ = false;
    std::string pg_sql_;
    std::vector<std::optional<std::string>> pg_params_;
    std::vector<int> pg_formats_;  // 1: binary (a blob), 0: text
    pg_result* pg_res_ = nullptr;
    int pg_row_ = -1;
};

class Db {
public:
    // Opens (creating) the file and sets WAL; throws DbError naming the path when the file
    // cannot be opened or is not a database. A postgresql:// URL connects to that server
    // instead (SQLITE_CANTOPEN naming the URL, without its password, when it cannot).
    explicit Db(const std::string& path);
    ~Db();
    Db(const Db&) = delete;
    Db& operator=(const Db&) = delete;

    void exec(std::string_view sql);
    std::int64_t last_insert_id() const;
    int changes() const;
    sqlite3* handle() { return db_; }
    [[noreturn]] void fail(int rc, std::string_view context) const;
    // The file, or the URL without its password.
    const std::string& path() const { return path_; }
    // What opens this database again: the file, or the full URL.
    const std::string& url() const { return url_; }
    bool is_postgres() const { return pg_ != nullptr; }
    pg_conn* pg() { return pg_; }
    // PostgreSQL: connects again when the connection was lost (a restarted server); throws a
    // storage fault while it cannot. Called before each transaction.
    void pg_ensure_connected();
    // PostgreSQL: the rows the last statement changed (changes()).
    void pg_set_changes(int n) { pg_changes_ = n; }
    bool pg_in_transaction() const { return pg_in_tx_; }
    void pg_set_in_transaction(bool on) { pg_in_tx_ = on; }
    // PostgreSQL: the requests sent to the server so far (each waits for its answer: a round
    // trip). What a store call costs on a remote database is mostly these; tests count them.
    std::int64_t pg_round_trips() const { return pg_round_trips_; }
    void pg_count_round_trip() { ++pg_round_trips_; }
    // PostgreSQL: runs one statement (PostgreSQL's spelling), prepared on this connection.
    pg_result* pg_run(const std::string& sql, const std::vector<std::optional<std::string>>& params,
                      const std::vector<int>& formats);

private:
    sqlite3* db_ = nullptr;
    pg_conn* pg_ = nullptr;
    // After a failed reconnect, requests fail at once until then instead of each waiting out
    // the connect timeout under the store's lock (localize keeps serving from memory).
    std::chrono::steady_clock::time_point pg_retry_at_{};
    int pg_changes_ = 0;
    std::int64_t pg_round_trips_ = 0;
    std::unique_ptr<pg::Prepared> pg_prepared_;
    bool pg_in_tx_ = false;
    std::string path_;
    std::string url_;
};

// BEGIN IMMEDIATE (PostgreSQL: BEGIN; a read: BEGIN, deferred) on construction, ROLLBACK unless commit() was called: one per request.
class Transaction {
public:
    // read: the transaction only reads, from one snapshot. SQLite gives that to any
    // transaction; PostgreSQL's default (READ COMMITTED, what writes use: they run one at a
    // time under a lock, and read what committed before them) would see other servers' commits
    // between two statements, so a read is REPEATABLE READ there.
    enum class Mode { write, read };
    // PostgreSQL: `then` (parameterless, PostgreSQL's spelling) runs right after BEGIN in the
    // same round trip, such as the write lock; SQLite runs it as a statement of its own.
    explicit Transaction(Db& db, Mode mode = Mode::write, std::string_view then = {});
    ~Transaction();
    // `last` (as `then`) runs just before COMMIT, in the same round trip on PostgreSQL; when it
    // fails nothing is committed (the destructor rolls back).
    void commit(std::string_view last = {});

private:
    Db& db_;
    bool done_ = false;
};

}  // namespace locus::store
