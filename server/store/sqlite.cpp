#include "store/sqlite.hpp"

#include <memory>
#include <utility>

namespace locus::store {

namespace {
struct Close {
    void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};

// An error from the connection: SQLite's message after `context`; a storage fault also carries
// the database file, so that the log can say which file is full, read-only or corrupt.
SqliteError error_from(sqlite3* db, int code, std::string_view context, const std::string& message) {
    SqliteError e(code, std::string(context) + message);
    if (!e.is_storage_fault()) return e;
    const char* file = sqlite3_db_filename(db, "main");
    e.file = file ? file : "";
    return e;
}
}  // namespace

Db::Db(const std::string& path) : path_(path) {
    sqlite3* raw = nullptr;
    const int rc = sqlite3_open_v2(path.c_str(), &raw,
                                   SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, nullptr);
    // Closed on every way out of here but the last line: a file that opens and then turns out
    // not to be a database used to leak its handle.
    std::unique_ptr<sqlite3, Close> handle(raw);
    if (rc != SQLITE_OK)
        throw SqliteError(rc, "cannot open database '" + path + "': " + (raw ? sqlite3_errmsg(raw) : "out of memory"), path);
    sqlite3_extended_result_codes(raw, 1);
    sqlite3_busy_timeout(raw, 5000);
    // WAL + synchronous=NORMAL survives a process kill; FULL would also survive power loss
    // at a large cost per commit, which a radio-map store does not need. Setting WAL reads the
    // file's header, so a file that is not a database fails here, at start-up.
    char* err = nullptr;
    if (sqlite3_exec(raw, "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL; PRAGMA foreign_keys=ON;", nullptr,
                     nullptr, &err) != SQLITE_OK) {
        const std::string msg = err ? err : sqlite3_errmsg(raw);
        sqlite3_free(err);
        throw SqliteError(sqlite3_extended_errcode(raw), "cannot open database '" + path + "': " + msg, path);
    }
    db_ = handle.release();
}

Db::~Db() {
    if (db_) sqlite3_close_v2(db_);
}

void Db::fail(int rc, std::string_view context) const {
    throw error_from(db_, sqlite3_extended_errcode(db_), std::string(context) + ": ",
                     std::string(sqlite3_errmsg(db_)) + " (" + std::to_string(rc) + ")");
}

void Db::exec(std::string_view sql) {
    char* err = nullptr;
    const std::string s(sql);
    const int rc = sqlite3_exec(db_, s.c_str(), nullptr, nullptr, &err);
    if (rc != SQLITE_OK) {
        const std::string msg = err ? err : "unknown error";
        sqlite3_free(err);
        throw error_from(db_, sqlite3_extended_errcode(db_), "", msg);
    }
}

std::int64_t Db::last_insert_id() const { return sqlite3_last_insert_rowid(db_); }
int Db::changes() const { return sqlite3_changes(db_); }

Stmt::Stmt(Db& db, std::string_view sql) : db_(db.handle()) {
    const int rc = sqlite3_prepare_v2(db_, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr);
    if (rc != SQLITE_OK) db.fail(rc, "prepare");
}

Stmt::~Stmt() {
    if (stmt_) sqlite3_finalize(stmt_);
}

Stmt::Stmt(Stmt&& other) noexcept : db_(other.db_), stmt_(std::exchange(other.stmt_, nullptr)) {}

namespace {
void check_bind(sqlite3* db, int rc) {
    if (rc != SQLITE_OK) throw error_from(db, rc, "bind: ", sqlite3_errmsg(db));
}
}  // namespace

Stmt& Stmt::bind_int64(int i, std::int64_t v) {
    check_bind(db_, sqlite3_bind_int64(stmt_, i, v));
    return *this;
}
Stmt& Stmt::bind(int i, double v) {
    check_bind(db_, sqlite3_bind_double(stmt_, i, v));
    return *this;
}
Stmt& Stmt::bind(int i, std::string_view v) {
    check_bind(db_, sqlite3_bind_text(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
    return *this;
}
Stmt& Stmt::bind_blob(int i, std::string_view bytes) {
    // SQLITE_STATIC: the caller's bytes outlive the step (a 20 MiB image is not copied twice).
    check_bind(db_, sqlite3_bind_blob64(stmt_, i, bytes.data(), bytes.size(), SQLITE_STATIC));
    return *this;
}
Stmt& Stmt::bind_null(int i) {
    check_bind(db_, sqlite3_bind_null(stmt_, i));
    return *this;
}

bool Stmt::step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    throw error_from(db_, sqlite3_extended_errcode(db_), "step: ", sqlite3_errmsg(db_));
}

void Stmt::run() {
    while (step()) {
    }
}

void Stmt::reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
}

std::int64_t Stmt::int64(int col) const { return sqlite3_column_int64(stmt_, col); }
double Stmt::real(int col) const { return sqlite3_column_double(stmt_, col); }
std::string Stmt::text(int col) const {
    const auto* p = sqlite3_column_text(stmt_, col);
    return p ? std::string(reinterpret_cast<const char*>(p), static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
             : std::string();
}
std::string Stmt::blob(int col) const {
    const auto* p = sqlite3_column_blob(stmt_, col);
    return p ? std::string(static_cast<const char*>(p), static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
             : std::string();
}
bool Stmt::is_null(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }
int Stmt::column_count() const { return sqlite3_column_count(stmt_); }
int Stmt::column_type(int col) const { return sqlite3_column_type(stmt_, col); }
std::string Stmt::column_name(int col) const { return sqlite3_column_name(stmt_, col); }

Transaction::Transaction(Db& db) : db_(db) { db_.exec("BEGIN IMMEDIATE"); }

Transaction::~Transaction() {
    if (!done_) {
        try {
            db_.exec("ROLLBACK");
        } catch (...) {
            // Nothing sensible to do: SQLite rolls back on its own when the statement failed.
        }
    }
}

void Transaction::commit() {
    db_.exec("COMMIT");
    done_ = true;
}

}  // namespace locus::store
