#pragma once
// Which backend the integration tests run on: LOCUS_TEST_DB_URL (set by
// scripts/with_postgres.sh) names a PostgreSQL cluster, on which every server under test gets
// a database of its own, created empty and dropped after; unset, each gets a temp SQLite file.
#include <string>

namespace locus::testing {

// The cluster URL from LOCUS_TEST_DB_URL when it is a PostgreSQL one; empty otherwise.
std::string postgres_cluster_url();
inline bool on_postgres() { return !postgres_cluster_url().empty(); }

// An empty PostgreSQL database on the cluster, dropped (its connections closed) on destruction.
class TestDatabase {
public:
    TestDatabase();
    ~TestDatabase();
    TestDatabase(const TestDatabase&) = delete;
    TestDatabase& operator=(const TestDatabase&) = delete;
    const std::string& url() const { return url_; }
    const std::string& name() const { return name_; }

private:
    std::string name_, url_;
};

// Runs one statement on the cluster's maintenance database; throws with PostgreSQL's message.
void cluster_exec(const std::string& sql);
// The same on the database `url` names.
void database_exec(const std::string& url, const std::string& sql);

}  // namespace locus::testing
