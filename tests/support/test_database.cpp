#include "test_database.hpp"

#include <libpq-fe.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <stdexcept>

namespace locus::testing {

std::string postgres_cluster_url() {
    const char* url = std::getenv("LOCUS_TEST_DB_URL");
    if (!url) return {};
    const std::string s(url);
    return s.starts_with("postgresql://") || s.starts_with("postgres://") ? s : std::string();
}

void cluster_exec(const std::string& sql) { database_exec(postgres_cluster_url(), sql); }

void database_exec(const std::string& url, const std::string& sql) {
    PGconn* c = PQconnectdb(url.c_str());
    if (PQstatus(c) != CONNECTION_OK) {
        const std::string msg = PQerrorMessage(c);
        PQfinish(c);
        throw std::runtime_error("cannot connect to the test cluster: " + msg);
    }
    PQsetNoticeProcessor(c, [](void*, const char*) {}, nullptr);  // "does not exist, skipping"
    PGresult* r = PQexec(c, sql.c_str());
    const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK || PQresultStatus(r) == PGRES_TUPLES_OK;
    const std::string msg = ok ? "" : PQresultErrorMessage(r);
    PQclear(r);
    PQfinish(c);
    if (!ok) throw std::runtime_error(sql + ": " + msg);
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
    cluster_exec("CREATE DATABASE " + name_);
    url_ = with_database(postgres_cluster_url(), name_);
}

TestDatabase::~TestDatabase() {
    try {
        cluster_exec("DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
    } catch (...) {
    }
}

}  // namespace locus::testing
