#pragma once
// Thin RAII layer over the SQLite C API: a connection, prepared statements, transactions.
#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <concepts>

namespace locus::store {

struct SqliteError : std::runtime_error {
    int code;
    std::string file;  // the database file, when the error is about it (empty otherwise)
    SqliteError(int c, const std::string& what, std::string db_file = {})
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
    sqlite3* db_;
    sqlite3_stmt* stmt_ = nullptr;
};

class Db {
public:
    // Opens (creating) the file and sets WAL; throws SqliteError naming the path when the file
    // cannot be opened or is not a database.
    explicit Db(const std::string& path);
    ~Db();
    Db(const Db&) = delete;
    Db& operator=(const Db&) = delete;

    void exec(std::string_view sql);
    std::int64_t last_insert_id() const;
    int changes() const;
    sqlite3* handle() { return db_; }
    [[noreturn]] void fail(int rc, std::string_view context) const;
    const std::string& path() const { return path_; }

private:
    sqlite3* db_ = nullptr;
    std::string path_;
};

// BEGIN IMMEDIATE on construction, ROLLBACK unless commit() was called: one per request.
class Transaction {
public:
    explicit Transaction(Db& db);
    ~Transaction();
    void commit();

private:
    Db& db_;
    bool done_ = false;
};

}  // namespace locus::store
