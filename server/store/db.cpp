#include "store/db.hpp"

#include <libpq-fe.h>

#include <charconv>
#include <cstdio>
#include <memory>
#include <utility>

#include "store/pg_detail.hpp"

namespace locus::store {

namespace {
struct Close {
    void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};

// An error from the connection: SQLite's message after `context`; a storage fault also carries
// the database file, so that the log can say which file is full, read-only or corrupt.
DbError error_from(sqlite3* db, int code, std::string_view context, const std::string& message) {
    DbError e(code, std::string(context) + message);
    if (!e.is_storage_fault()) return e;
    const char* file = sqlite3_db_filename(db, "main");
    e.file = file ? file : "";
    return e;
}
}  // namespace

Db::Db(const std::string& path) : path_(path), url_(path) {
    if (is_postgres_url(path)) {
        path_ = redacted_url(path);
        pg_ = pg::connect(path);
        pg_prepared_ = std::make_unique<pg::Prepared>();
        return;
    }
    sqlite3* raw = nullptr;
    const int rc = sqlite3_open_v2(path.c_str(), &raw,
                                   SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, nullptr);
    // Closed on every way out of here but the last line: a file that opens and then turns out
    // not to be a database used to leak its handle.
    std::unique_ptr<sqlite3, Close> handle(raw);
    if (rc != SQLITE_OK)
        throw DbError(rc, "cannot open database '" + path + "': " + (raw ? sqlite3_errmsg(raw) : "out of memory"), path);
    sqlite3_extended_result_codes(raw, 1);
    sqlite3_busy_timeout(raw, 5000);
    // WAL + synchronous=NORMAL survives a process kill; FULL would also survive power loss
    // at a large cost per commit, which a radio-map store does not need. Setting WAL reads the
    // file's header, so a file that is not a database fails here, at start-up.
    // The log is copied back every 256 pages (1 MiB; SQLite's default is 1,000) and cut back
    // to 1 MiB once copied: what clients' writes add to the disk is then their rows and at
    // most about a MiB of log, not the 4 MB the default log keeps after any steady writing.
    char* err = nullptr;
    if (sqlite3_exec(raw,
                     "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL; PRAGMA foreign_keys=ON; "
                     "PRAGMA wal_autocheckpoint=256; PRAGMA journal_size_limit=1048576;",
                     nullptr, nullptr, &err) != SQLITE_OK) {
        const std::string msg = err ? err : sqlite3_errmsg(raw);
        sqlite3_free(err);
        throw DbError(sqlite3_extended_errcode(raw), "cannot open database '" + path + "': " + msg, path);
    }
    db_ = handle.release();
}

Db::~Db() {
    if (db_) sqlite3_close_v2(db_);
    pg::close(pg_);
}

void Db::pg_ensure_connected() {
    if (PQstatus(pg_) == CONNECTION_OK) return;
    const auto now = std::chrono::steady_clock::now();
    if (now < pg_retry_at_)
        throw DbError(SQLITE_IOERR, "PostgreSQL at '" + path_ + "' is unreachable (retrying once a second)", path_);
    PQreset(pg_);
    pg_prepared_ = std::make_unique<pg::Prepared>();  // they went with the old session
    if (PQstatus(pg_) != CONNECTION_OK) {
        pg_retry_at_ = std::chrono::steady_clock::now() + std::chrono::seconds(1);
        throw DbError(SQLITE_IOERR, "PostgreSQL at '" + path_ + "' is unreachable: " + PQerrorMessage(pg_), path_);
    }
}

pg_result* Db::pg_run(const std::string& sql, const std::vector<std::optional<std::string>>& params,
                      const std::vector<int>& formats) {
    return pg::run(pg_, sql, params, formats, pg_prepared_.get(), &pg_round_trips_);
}

void Db::fail(int rc, std::string_view context) const {
    throw error_from(db_, sqlite3_extended_errcode(db_), std::string(context) + ": ",
                     std::string(sqlite3_errmsg(db_)) + " (" + std::to_string(rc) + ")");
}

void Db::exec(std::string_view sql) {
    if (pg_) {
        ++pg_round_trips_;
        pg::exec(pg_, pg::to_postgres(sql));
        return;
    }
    char* err = nullptr;
    const std::string s(sql);
    const int rc = sqlite3_exec(db_, s.c_str(), nullptr, nullptr, &err);
    if (rc != SQLITE_OK) {
        const std::string msg = err ? err : "unknown error";
        sqlite3_free(err);
        throw error_from(db_, sqlite3_extended_errcode(db_), "", msg);
    }
}

std::int64_t Db::last_insert_id() const {
    if (pg_) {
        // The identity column's sequence, as used by this session's last INSERT.
        ++const_cast<Db*>(this)->pg_round_trips_;
        PGresult* r = pg::run(pg_, "SELECT lastval()", {}, {});
        const std::int64_t id = std::atoll(PQgetvalue(r, 0, 0));
        PQclear(r);
        return id;
    }
    return sqlite3_last_insert_rowid(db_);
}
int Db::changes() const { return pg_ ? pg_changes_ : sqlite3_changes(db_); }

Stmt::Stmt(Db& db, std::string_view sql) : db_(db.handle()), owner_(&db), pg_(db.is_postgres()) {
    if (pg_) {
        pg_sql_ = pg::to_postgres(sql);
        return;
    }
    const int rc = sqlite3_prepare_v2(db_, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr);
    if (rc != SQLITE_OK) db.fail(rc, "prepare");
}

Stmt::~Stmt() {
    if (stmt_) sqlite3_finalize(stmt_);
    pg::clear(pg_res_);
}

Stmt::Stmt(Stmt&& other) noexcept
    : db_(other.db_), stmt_(std::exchange(other.stmt_, nullptr)), owner_(other.owner_), pg_(other.pg_),
      pg_sql_(std::move(other.pg_sql_)), pg_params_(std::move(other.pg_params_)), pg_formats_(std::move(other.pg_formats_)),
      pg_res_(std::exchange(other.pg_res_, nullptr)), pg_row_(other.pg_row_) {}

namespace {
void set_param(std::vector<std::optional<std::string>>& params, std::vector<int>& formats, int i,
               std::optional<std::string> v, int format) {
    const auto at = static_cast<std::size_t>(i - 1);
    if (params.size() <= at) {
        params.resize(at + 1);
        formats.resize(at + 1, 0);
    }
    params[at] = std::move(v);
    formats[at] = format;
}
}  // namespace

void Stmt::pg_execute() {
    // A statement outside a transaction may reconnect; inside one, the lost transaction must fail.
    if (!owner_->pg_in_transaction()) owner_->pg_ensure_connected();
    pg::clear(pg_res_);
    pg_res_ = nullptr;
    owner_->pg_count_round_trip();
    pg_res_ = owner_->pg_run(pg_sql_, pg_params_, pg_formats_);
    owner_->pg_set_changes(pg::changed_rows(pg_res_));
    pg_row_ = -1;
}

const char* Stmt::pg_value(int col) const { return pg::value(pg_res_, pg_row_, col); }

namespace {
void check_bind(sqlite3* db, int rc) {
    if (rc != SQLITE_OK) throw error_from(db, rc, "bind: ", sqlite3_errmsg(db));
}
}  // namespace

Stmt& Stmt::bind_int64(int i, std::int64_t v) {
    if (pg_) {
        set_param(pg_params_, pg_formats_, i, std::to_string(v), 0);
        return *this;
    }
    check_bind(db_, sqlite3_bind_int64(stmt_, i, v));
    return *this;
}
Stmt& Stmt::bind(int i, double v) {
    if (pg_) {
        // The shortest text that reads back as the same double: a mean stays bit-exact.
        char buf[64];
        const auto r = std::to_chars(buf, buf + sizeof buf, v);
        set_param(pg_params_, pg_formats_, i, std::string(buf, r.ptr), 0);
        return *this;
    }
    check_bind(db_, sqlite3_bind_double(stmt_, i, v));
    return *this;
}
Stmt& Stmt::bind(int i, std::string_view v) {
    if (pg_) {
        set_param(pg_params_, pg_formats_, i, std::string(v), 0);
        return *this;
    }
    check_bind(db_, sqlite3_bind_text(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
    return *this;
}
Stmt& Stmt::bind_blob(int i, std::string_view bytes) {
    if (pg_) {
        set_param(pg_params_, pg_formats_, i, std::string(bytes), 1);
        return *this;
    }
    // SQLITE_STATIC: the caller's bytes outlive the step (a 20 MiB image is not copied twice).
    check_bind(db_, sqlite3_bind_blob64(stmt_, i, bytes.data(), bytes.size(), SQLITE_STATIC));
    return *this;
}
Stmt& Stmt::bind_null(int i) {
    if (pg_) {
        set_param(pg_params_, pg_formats_, i, std::nullopt, 0);
        return *this;
    }
    check_bind(db_, sqlite3_bind_null(stmt_, i));
    return *this;
}

bool Stmt::step() {
    if (pg_) {
        if (!pg_res_) pg_execute();
        return ++pg_row_ < pg::row_count(pg_res_);
    }
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
    if (pg_) {
        pg::clear(pg_res_);
        pg_res_ = nullptr;
        pg_params_.clear();
        pg_formats_.clear();
        return;
    }
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
}

std::int64_t Stmt::int64(int col) const {
    if (pg_) {
        // A boolean (EXISTS (…)) reads as SQLite gives it: 1 or 0.
        const char* v = pg_value(col);
        if (*v == 't') return 1;
        if (*v == 'f') return 0;
        return std::strtoll(v, nullptr, 10);
    }
    return sqlite3_column_int64(stmt_, col);
}
double Stmt::real(int col) const {
    if (pg_) return std::strtod(pg_value(col), nullptr);
    return sqlite3_column_double(stmt_, col);
}
std::string Stmt::text(int col) const {
    if (pg_) return pg_value(col);
    const auto* p = sqlite3_column_text(stmt_, col);
    return p ? std::string(reinterpret_cast<const char*>(p), static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
             : std::string();
}
std::string Stmt::blob(int col) const {
    if (pg_) return pg::is_bytea(pg_res_, col) ? pg::unescape_bytea(pg_value(col)) : std::string(pg_value(col));
    const auto* p = sqlite3_column_blob(stmt_, col);
    return p ? std::string(static_cast<const char*>(p), static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
             : std::string();
}
bool Stmt::is_null(int col) const {
    if (pg_) return pg::is_null(pg_res_, pg_row_, col);
    return sqlite3_column_type(stmt_, col) == SQLITE_NULL;
}
int Stmt::column_count() const {
    if (pg_) return pg_res_ ? pg::column_count(pg_res_) : 0;  // known once it ran
    return sqlite3_column_count(stmt_);
}
int Stmt::column_type(int col) const {
    if (pg_) return pg::is_null(pg_res_, pg_row_, col) ? SQLITE_NULL : pg::column_type(pg_res_, col);
    return sqlite3_column_type(stmt_, col);
}
std::string Stmt::column_name(int col) const {
    if (pg_) return pg::column_name(pg_res_, col);
    return sqlite3_column_name(stmt_, col);
}

Transaction::Transaction(Db& db, Mode mode, std::string_view then) : db_(db) {
    if (db_.is_postgres()) {
        db_.pg_ensure_connected();
        std::string sql = mode == Mode::read ? "BEGIN ISOLATION LEVEL REPEATABLE READ READ ONLY" : "BEGIN";
        if (!then.empty()) sql.append("; ").append(then);
        // One request: the simple query protocol runs the text's statements in order and stops at
        // the first that fails, which leaves the transaction open (BEGIN ran) but aborted; no
        // destructor runs for a constructor that throws, so it is rolled back here.
        db_.pg_count_round_trip();
        try {
            pg::exec(db_.pg(), sql);
        } catch (...) {
            try {
                pg::exec(db_.pg(), "ROLLBACK");
            } catch (...) {
                // The connection is gone: so is its transaction.
            }
            throw;
        }
        db_.pg_set_in_transaction(true);
        return;
    }
    // A read takes no lock until its first statement, and then only its snapshot (WAL): a long
    // one (an export being written out) does not hold writers back.
    db_.exec(mode == Mode::read ? "BEGIN" : "BEGIN IMMEDIATE");
    if (!then.empty()) db_.exec(then);
}

Transaction::~Transaction() {
    if (db_.is_postgres()) db_.pg_set_in_transaction(false);
    if (!done_) {
        try {
            db_.exec("ROLLBACK");
        } catch (...) {
            // Nothing sensible to do: SQLite rolls back on its own when the statement failed.
        }
    }
}

void Transaction::commit(std::string_view last) {
    if (db_.is_postgres()) {
        std::string sql(last);
        if (!sql.empty()) sql += "; ";
        sql += "COMMIT";
        db_.pg_count_round_trip();
        const std::string status = pg::exec(db_.pg(), sql);
        db_.pg_set_in_transaction(false);
        done_ = true;
        // COMMIT of a transaction a swallowed failure aborted rolls it back and says so only in
        // its command status ("ROLLBACK", with no error): nothing was written, so say it.
        if (status != "COMMIT")
            throw DbError(SQLITE_ABORT, "commit: the transaction was rolled back (a statement in it had failed)");
        return;
    }
    if (!last.empty()) db_.exec(last);
    db_.exec("COMMIT");
    done_ = true;
}

}  // namespace locus::store
