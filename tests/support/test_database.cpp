#include "test_database.hpp"

#include <libpq-fe.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

namespace locus::testing {

std::string postgres_cluster_url() {
    const char* url = std::getenv("LOCUS_TEST_DB_URL");
    if (!url) return {};
    const std::string s(url);
    return s.starts_with("postgresql://") || s.starts_with("postgres://") ? s : std::string();
}

namespace {
struct Conn {
    PGconn* c = nullptr;
    ~Conn() { PQfinish(c); }
};

// One statement on an open connection; throws with PostgreSQL's message.
void exec_on(PGconn* c, const std::string& sql) {
    PGresult* r = PQexec(c, sql.c_str());
    const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK || PQresultStatus(r) == PGRES_TUPLES_OK;
    const std::string msg = ok ? "" : PQresultErrorMessage(r);
    PQclear(r);
    if (!ok) throw std::runtime_error(sql + ": " + msg);
}

PGconn* open_connection(const std::string& url) {
    PGconn* c = PQconnectdb(url.c_str());
    if (PQstatus(c) != CONNECTION_OK) {
        const std::string msg = PQerrorMessage(c);
        PQfinish(c);
        throw std::runtime_error("cannot connect to the test cluster: " + msg);
    }
    PQsetNoticeProcessor(c, [](void*, const char*) {}, nullptr);  // "does not exist, skipping"
    return c;
}

// The maintenance connection, opened once per test process: a PostgreSQL connection is a new
// backend process, and three of them per test database were a fifth of the PostgreSQL pass's
// CPU (docs/testing.md, "How long the build takes"). Never destroyed, so that a database dropped
// by a static's destructor at exit still finds it; the process's exit closes it.
struct Cluster {
    std::mutex mutex;
    PGconn* c = nullptr;
    PGconn* connection() {  // with `mutex` held
        if (c && PQstatus(c) != CONNECTION_OK) {
            PQfinish(c);
            c = nullptr;
        }
        if (!c) c = open_connection(postgres_cluster_url());
        return c;
    }
};
Cluster& cluster() {
    static Cluster* const it = new Cluster;
    return *it;
}
}  // namespace

void cluster_exec(const std::string& sql) {
    const std::lock_guard<std::mutex> lock(cluster().mutex);
    try {
        exec_on(cluster().connection(), sql);
    } catch (const std::runtime_error&) {
        // A connection a test's pg_terminate_backend ended shows only when next used: once more
        // on a new one. A statement PostgreSQL refused throws again.
        if (PQstatus(cluster().c) == CONNECTION_OK) throw;
        exec_on(cluster().connection(), sql);
    }
}

void database_exec(const std::string& url, const std::string& sql) {
    Conn conn{open_connection(url)};
    exec_on(conn.c, sql);
}

namespace {
// The cluster URL with its database name replaced.
std::string with_database(const std::string& cluster, const std::string& name) {
    const auto scheme = cluster.find("://");
    const auto slash = cluster.find('/', scheme + 3);
    const auto query = cluster.find('?', scheme + 3);
    const std::string base = cluster.substr(0, slash == std::string::npos ? query : slash);
    return base + "/" + name + (query == std::string::npos ? "" : cluster.substr(query));
}
}  // namespace

TestDatabase::TestDatabase() {
    static std::atomic<int> next{0};
    name_ = "locus_t_" + std::to_string(::getpid()) + "_" + std::to_string(next++);
    cluster_exec("DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
    // FILE_COPY (PostgreSQL 15+) copies template1's files instead of writing each block to the
    // WAL: 40 % less CPU per database, and the cluster does not fsync anyway.
    const bool file_copy = [] {
        const std::lock_guard<std::mutex> lock(cluster().mutex);
        return PQserverVersion(cluster().connection()) >= 150000;
    }();
    cluster_exec("CREATE DATABASE " + name_ + (file_copy ? " STRATEGY FILE_COPY" : ""));
    url_ = with_database(postgres_cluster_url(), name_);
}

TestDatabase::~TestDatabase() {
    try {
        cluster_exec("DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
    } catch (...) {
    }
}

}  // namespace locus::testing
