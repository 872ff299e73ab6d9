#include <libpq-fe.h>

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <utility>

#include "store/pg_detail.hpp"

namespace locus::store {

bool is_postgres_url(std::string_view url) {
    return url.starts_with("postgresql://") || url.starts_with("postgres://");
}

namespace {
// Where scheme://user:password@host… holds its password: [first, last), the ':' at first − 1;
// nullopt when the URL's user part has none.
std::optional<std::pair<std::size_t, std::size_t>> password_span(std::string_view url) {
    const auto scheme = url.find("://");
    if (scheme == std::string_view::npos) return std::nullopt;
    const auto at = url.find('@', scheme + 3), slash = url.find('/', scheme + 3);
    if (at == std::string_view::npos || (slash != std::string_view::npos && slash < at)) return std::nullopt;
    const auto colon = url.find(':', scheme + 3);
    if (colon == std::string_view::npos || colon > at) return std::nullopt;
    return std::pair{colon + 1, at};
}
}  // namespace

std::string redacted_url(std::string_view url) {
    // scheme://user:password@host… keeps user@host…; a password=… parameter is cut too.
    std::string out(url);
    if (const auto pw = password_span(url)) out.erase(pw->first - 1, pw->second - pw->first + 1);
    // Every password=… and sslpassword=… parameter, not only the first.
    for (auto pw = out.find("password="); pw != std::string::npos; pw = out.find("password=", pw + 12)) {
        const auto end = out.find('&', pw);
        out.replace(pw, (end == std::string::npos ? out.size() : end) - pw, "password=***");
    }
    return out;
}

namespace {
// libpq's own message can quote the URL's password (a bad %-escape in it is echoed): cut the
// password's text, as written and %-decoded, out of whatever it says.
std::string without_password(std::string msg, std::string_view url) {
    const auto pw = password_span(url);
    if (!pw) return msg;
    const std::string raw(url.substr(pw->first, pw->second - pw->first));
    std::string decoded;
    for (std::size_t i = 0; i < raw.size(); ++i) {
        if (raw[i] == '%' && i + 2 < raw.size() && std::isxdigit(static_cast<unsigned char>(raw[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(raw[i + 2]))) {
            decoded += static_cast<char>(std::stoi(raw.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            decoded += raw[i];
        }
    }
    for (const std::string& secret : {raw, decoded}) {
        if (secret.empty()) continue;
        for (auto i = msg.find(secret); i != std::string::npos; i = msg.find(secret, i + 3)) msg.replace(i, secret.size(), "***");
    }
    return msg;
}
}  // namespace

namespace pg {

namespace {
bool starts_with_word(std::string_view sql, std::size_t i, std::string_view word) {
    if (sql.size() - i < word.size()) return false;
    for (std::size_t k = 0; k < word.size(); ++k)
        if (std::toupper(static_cast<unsigned char>(sql[i + k])) != word[k]) return false;
    return true;
}
constexpr Oid kTextOid = 25;  // pg_type.h
bool is_identifier_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
}  // namespace

std::string to_postgres(std::string_view sql) {
    static constexpr std::string_view kNow = "strftime('%Y-%m-%dT%H:%M:%fZ', 'now')";
    static constexpr std::string_view kPgNow =
        "to_char(now() AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"')";
    std::string out;
    out.reserve(sql.size() + 16);
    bool ignore = false;
    int next = 0;
    for (std::size_t i = 0; i < sql.size();) {
        if (sql.substr(i).starts_with(kNow)) {
            out += kPgNow;
            i += kNow.size();
        } else if (sql[i] == '\'') {  // quoted text, '' inside it included
            const auto end = sql.find('\'', i + 1);
            const auto stop = end == std::string_view::npos ? sql.size() : end + 1;
            out.append(sql.substr(i, stop - i));
            i = stop;
        } else if (sql[i] == '?') {
            std::size_t j = i + 1;
            while (j < sql.size() && std::isdigit(static_cast<unsigned char>(sql[j]))) ++j;
            if (j > i + 1) {
                out += '$';
                out.append(sql.substr(i + 1, j - i - 1));
            } else {
                out += '$' + std::to_string(++next);
            }
            i = j;
        } else if ((sql.substr(i).starts_with("xmin") || sql.substr(i).starts_with("xmax")) &&
                   (i == 0 || !is_identifier_char(sql[i - 1])) &&
                   (i + 4 == sql.size() || !is_identifier_char(sql[i + 4]))) {
            // xmin and xmax are PostgreSQL's system columns: room_rects calls them rect_xmin, rect_xmax.
            out += "rect_";
            out.append(sql.substr(i, 4));
            i += 4;
        } else if (starts_with_word(sql, i, "INSERT OR IGNORE ")) {
            out += "INSERT ";
            i += std::strlen("INSERT OR IGNORE ");
            ignore = true;
        } else {
            out += sql[i++];
        }
    }
    if (ignore) out += " ON CONFLICT DO NOTHING";
    return out;
}

pg_conn* connect(const std::string& url) {
    // A host that does not answer would otherwise hold start-up, a request's reconnect or the
    // shutdown of the change watcher for the kernel's TCP timeout (minutes); the URL's own
    // connect_timeout, when it has one, wins (it comes later).
    const char* const keys[] = {"connect_timeout", "dbname", nullptr};
    const char* const values[] = {"5", url.c_str(), nullptr};
    PGconn* c = PQconnectdbParams(keys, values, 1);
    if (!c) throw DbError(SQLITE_CANTOPEN, "cannot connect to PostgreSQL at '" + redacted_url(url) + "': out of memory");
    if (PQstatus(c) != CONNECTION_OK) {
        std::string msg = without_password(PQerrorMessage(c), url);
        while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
        PQfinish(c);
        throw DbError(SQLITE_CANTOPEN, "cannot connect to PostgreSQL at '" + redacted_url(url) + "': " + msg,
                          redacted_url(url));
    }
    // Notices (a CREATE … IF NOT EXISTS that did nothing) are not errors: keep them off stderr.
    PQsetNoticeProcessor(c, [](void*, const char*) {}, nullptr);
    return c;
}

void close(pg_conn* c) {
    if (c) PQfinish(c);
}

DbError error_of(pg_conn* c, pg_result* r, std::string_view context) {
    const char* state = r ? PQresultErrorField(r, PG_DIAG_SQLSTATE) : nullptr;
    std::string msg = r ? PQresultErrorMessage(r) : "";
    if (msg.empty()) msg = c ? PQerrorMessage(c) : "no connection";
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
    const std::string code = state ? state : "";
    int rc = SQLITE_ERROR;
    if (!c || PQstatus(c) != CONNECTION_OK || code.empty() || code.starts_with("08") || code.starts_with("57P") ||
        code.starts_with("53") || code.starts_with("58"))
        rc = SQLITE_IOERR;  // the database, not the request: 503, and the next request reconnects
    else if (code == "23505") rc = SQLITE_CONSTRAINT_UNIQUE;
    else if (code == "23503") rc = SQLITE_CONSTRAINT_FOREIGNKEY;
    else if (code == "23514") rc = SQLITE_CONSTRAINT_CHECK;
    else if (code == "23502") rc = SQLITE_CONSTRAINT_NOTNULL;
    else if (code.starts_with("23")) rc = SQLITE_CONSTRAINT;
    else if (code == "40001" || code == "40P01" || code == "55P03") rc = SQLITE_BUSY;
    DbError e(rc, std::string(context) + msg + (code.empty() ? "" : " (" + code + ")"));
    if (e.is_storage_fault() && c) e.file = std::string(PQdb(c) ? PQdb(c) : "");
    return e;
}

std::string exec(pg_conn* c, std::string_view sql) {
    PGresult* r = PQexec(c, std::string(sql).c_str());
    const auto st = PQresultStatus(r);
    if (st != PGRES_COMMAND_OK && st != PGRES_TUPLES_OK && st != PGRES_EMPTY_QUERY) {
        DbError e = error_of(c, r, "");
        PQclear(r);
        throw e;
    }
    std::string status = PQcmdStatus(r);
    PQclear(r);
    return status;
}

namespace {
pg_result* run_once(pg_conn* c, const std::string& sql, const std::vector<std::optional<std::string>>& params,
                    const std::vector<int>& formats, Prepared* prepared, std::int64_t* round_trips, bool may_retry) {
    std::vector<const char*> values(params.size());
    std::vector<int> lengths(params.size());
    for (std::size_t i = 0; i < params.size(); ++i) {
        values[i] = params[i] ? params[i]->data() : nullptr;
        lengths[i] = params[i] ? static_cast<int>(params[i]->size()) : 0;
    }
    // A parameter the statement does not use (LIMIT ?2 OFFSET ?3 without ?1) has no type to
    // infer: it is sent as text.
    std::vector<Oid> types(params.size(), 0);
    for (std::size_t i = 0; i < params.size(); ++i) {
        std::string mark = std::to_string(i + 1);
        mark.insert(mark.begin(), '$');
        bool used = false;
        for (auto at = sql.find(mark); at != std::string::npos && !used; at = sql.find(mark, at + 1)) {
            const auto end = at + mark.size();
            used = end == sql.size() || !std::isdigit(static_cast<unsigned char>(sql[end]));
        }
        if (!used) types[i] = kTextOid;
    }
    const int n = static_cast<int>(params.size());
    // Whether this statement runs outside a transaction: only then may a failure caused by a
    // stale cache be retried (inside one the failure has aborted the transaction already).
    const bool autocommit = PQtransactionStatus(c) == PQTRANS_IDLE;
    if (prepared && prepared->stale_on_server && autocommit) {
        // The cache was emptied inside a transaction: what the session still holds under the
        // old names (a statement whose plan went stale) goes now, so that nothing leaks.
        if (round_trips) ++*round_trips;
        exec(c, "DEALLOCATE ALL");
        prepared->stale_on_server = false;
    }
    const std::string* name = nullptr;
    if (prepared) {
        const std::string key = sql + '\0' + std::to_string(n);
        auto at = prepared->names.find(key);
        if (at == prepared->names.end() && prepared->names.size() < prepared->limit) {
            std::string fresh = "locus_" + std::to_string(prepared->next++);
            if (round_trips) ++*round_trips;
            PGresult* p = PQprepare(c, fresh.c_str(), sql.c_str(), n, types.data());
            if (PQresultStatus(p) != PGRES_COMMAND_OK) {
                DbError e = error_of(c, p, "step: ");
                PQclear(p);
                throw e;
            }
            PQclear(p);
            at = prepared->names.emplace(key, std::move(fresh)).first;
        }
        if (at != prepared->names.end()) name = &at->second;
    }
    PGresult* r = name ? PQexecPrepared(c, name->c_str(), n, values.data(), lengths.data(), formats.data(), 0)
                       : PQexecParams(c, sql.c_str(), n, types.data(), values.data(), lengths.data(), formats.data(), 0);
    const auto st = PQresultStatus(r);
    if (st != PGRES_COMMAND_OK && st != PGRES_TUPLES_OK) {
        const char* state = PQresultErrorField(r, PG_DIAG_SQLSTATE);
        // 26000: the name is gone on the server (DISCARD ALL, DEALLOCATE, a pooler that hands
        // the session's statements to another client); 0A000 "cached plan must not change result
        // type": a table the statement reads changed. Either way the cache no longer says what
        // the session holds: it is emptied (whatever remains on the server is deallocated
        // before the next statement outside a transaction), and a statement outside a
        // transaction runs again once, prepared afresh (safe for a write too: both errors come
        // before the statement executes). Inside one the transaction is aborted whatever is
        // done here: it fails as any failed statement does.
        const bool stale = name && state && (std::strcmp(state, "26000") == 0 || std::strcmp(state, "0A000") == 0);
        if (stale) {
            prepared->names.clear();
            prepared->stale_on_server = true;
        }
        if (stale && may_retry && autocommit && PQtransactionStatus(c) == PQTRANS_IDLE) {
            PQclear(r);
            if (round_trips) ++*round_trips;
            return run_once(c, sql, params, formats, prepared, round_trips, false);
        }
        DbError e = error_of(c, r, "step: ");
        PQclear(r);
        throw e;
    }
    return r;
}
}  // namespace

pg_result* run(pg_conn* c, const std::string& sql, const std::vector<std::optional<std::string>>& params,
               const std::vector<int>& formats, Prepared* prepared, std::int64_t* round_trips) {
    return run_once(c, sql, params, formats, prepared, round_trips, true);
}

void clear(pg_result* r) {
    if (r) PQclear(r);
}
int row_count(const pg_result* r) { return PQntuples(r); }
int column_count(const pg_result* r) { return PQnfields(r); }
bool is_null(const pg_result* r, int row, int col) { return PQgetisnull(r, row, col) != 0; }
// Out of range (a read after step() said there is no row) answers "" as SQLite answers 0 / an
// empty text there; libpq would answer a null pointer.
const char* value(const pg_result* r, int row, int col) {
    if (!r || row < 0 || row >= PQntuples(r) || col < 0 || col >= PQnfields(r)) return "";
    return PQgetvalue(r, row, col);
}
std::string column_name(const pg_result* r, int col) { return PQfname(r, col); }

namespace {
// Type oids from PostgreSQL's pg_type.h (stable across versions).
constexpr Oid kBool = 16, kBytea = 17, kInt8 = 20, kInt2 = 21, kInt4 = 23, kFloat4 = 700, kFloat8 = 701, kNumeric = 1700;
}  // namespace

bool is_bytea(const pg_result* r, int col) { return PQftype(r, col) == kBytea; }

int column_type(const pg_result* r, int col) {
    switch (PQftype(r, col)) {
        case kBool:
        case kInt8:
        case kInt2:
        case kInt4: return SQLITE_INTEGER;
        case kFloat4:
        case kFloat8:
        case kNumeric: return SQLITE_FLOAT;
        case kBytea: return SQLITE_BLOB;
        default: return SQLITE_TEXT;
    }
}

std::string unescape_bytea(const char* text) {
    std::size_t n = 0;
    unsigned char* bytes = PQunescapeBytea(reinterpret_cast<const unsigned char*>(text), &n);
    if (!bytes) throw DbError(SQLITE_NOMEM, "cannot decode a bytea value");
    std::string out(reinterpret_cast<const char*>(bytes), n);
    PQfreemem(bytes);
    return out;
}

std::string literal(pg_conn* c, std::string_view text) {
    char* quoted = PQescapeLiteral(c, text.data(), text.size());
    if (!quoted) throw error_of(c, nullptr, "quoting a literal: ");
    std::string out(quoted);
    PQfreemem(quoted);
    return out;
}

int changed_rows(pg_result* r) {
    const char* n = PQcmdTuples(r);
    return n && *n ? std::atoi(n) : 0;
}

}  // namespace pg
}  // namespace locus::store
