#include "store/migrations.hpp"

#include <string>

namespace locus::store {

namespace {
bool foreign_keys_on(Db& db) {
    Stmt q(db, "PRAGMA foreign_keys");
    return q.step() && q.int64(0) != 0;
}
std::string newer_message(int version, std::size_t known) {
    return "database schema version " + std::to_string(version) + " is newer than this server understands (" +
           std::to_string(known) + ")";
}

int migrate_postgres(Db& db) {
    const auto& all = server::pg_migrations();
    Transaction tx(db);
    // Any constant: the lock only keeps two servers from migrating at once.
    db.exec("SELECT pg_advisory_xact_lock(7343467)");
    db.exec("CREATE TABLE IF NOT EXISTS locus_schema (id BIGINT PRIMARY KEY CHECK (id = 1), version BIGINT NOT NULL)");
    db.exec("INSERT INTO locus_schema (id, version) VALUES (1, 0) ON CONFLICT (id) DO NOTHING");
    int version = 0;
    {
        Stmt q(db, "SELECT version FROM locus_schema WHERE id = 1");
        q.step();
        version = static_cast<int>(q.int64(0));
    }
    if (version > static_cast<int>(all.size())) throw DbError(0, newer_message(version, all.size()));
    // PostgreSQL's DDL is transactional and its foreign keys stay checked: every migration
    // commits, or none, with the version.
    for (auto i = static_cast<std::size_t>(version); i < all.size(); ++i) db.exec(all[i]);
    Stmt set(db, "UPDATE locus_schema SET version = ? WHERE id = 1");
    set.bind(1, static_cast<std::int64_t>(all.size())).run();
    tx.commit();
    return static_cast<int>(all.size());
}
}  // namespace

int migrate(Db& db) {
    if (db.is_postgres()) return migrate_postgres(db);
    const auto& all = server::migrations();
    int version = 0;
    {
        Stmt q(db, "PRAGMA user_version");
        q.step();
        version = static_cast<int>(q.int64(0));
    }
    if (version > static_cast<int>(all.size()))
        throw DbError(0, newer_message(version, all.size()));
    if (version == static_cast<int>(all.size())) return version;

    // A migration that rebuilds a table drops the old one: with foreign keys on, that DROP would
    // delete every child row through ON DELETE CASCADE. The pragma is a no-op inside a
    // transaction, so it is switched off around them, and each migration proves with
    // foreign_key_check that it left no dangling reference before it commits.
    const bool enforce = foreign_keys_on(db);
    db.exec("PRAGMA foreign_keys=OFF");
    struct Restore {
        Db& db;
        bool on;
        ~Restore() {
            try {
                if (on) db.exec("PRAGMA foreign_keys=ON");
            } catch (...) {
            }
        }
    } restore{db, enforce};
    for (auto i = static_cast<std::size_t>(version); i < all.size(); ++i) {
        Transaction tx(db);
        db.exec(all[i]);
        {
            Stmt check(db, "PRAGMA foreign_key_check");
            if (check.step())
                throw DbError(SQLITE_CONSTRAINT_FOREIGNKEY,
                                  "migration " + std::to_string(i + 1) + " leaves a row of table '" + check.text(0) +
                                      "' pointing at a missing row of '" + check.text(2) + "'");
        }
        db.exec("PRAGMA user_version = " + std::to_string(i + 1));
        tx.commit();
        version = static_cast<int>(i + 1);
    }
    return version;
}

}  // namespace locus::store
