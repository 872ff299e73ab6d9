// SqlStore's PostgreSQL-only parts: the constructor's change watcher, the write lock and
// the change announcement (pg_changes.hpp).
#include <unistd.h>

#include <random>

#include "store/sql_store.hpp"

namespace locus::store {

namespace {
std::string new_origin() {
    std::random_device rd;
    return std::to_string(::getpid()) + "-" + std::to_string(rd()) + std::to_string(rd());
}
}  // namespace

void SqlStore::pg_start_watching() {
    origin_ = new_origin();
    // Other servers' changes reach this server's subscribers as its own writes do.
    watcher_ = std::make_unique<ChangeWatcher>(db_.url(), origin_, [this](const std::vector<Change>& c) { publish(c); });
}

std::string_view SqlStore::pg_write_lock() {
    // Any constant (not migrate's): every server's writes queue on it until their commit.
    return "SELECT pg_advisory_xact_lock(7343468)";
}

std::string SqlStore::pg_announcement(const std::vector<Change>& changes) { return announcement(db_, origin_, changes); }

std::unique_ptr<Store> open(const std::string& url) {
    if (url.starts_with("sqlite:")) return std::make_unique<SqlStore>(url.substr(7));
    return std::make_unique<SqlStore>(url);
}

}  // namespace locus::store
