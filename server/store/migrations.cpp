#include "store/migrations.hpp"

#include <string>

namespace locus::store {

namespace {
bool foreign_keys_on(Db& db) {
    Stmt q(db, "PRAGMA foreign_keys");
    return q.step() && q.int64(0) != 0;
}
}  // namespace

int migrate(Db& db) {
    const auto& all = server::migrations();
    int version = 0;
    {
        Stmt q(db, "PRAGMA user_version");
        q.step();
        version = static_cast<int>(q.int64(0));
    }
    if (version > static_cast<int>(all.size()))
        throw SqliteError(0, "database schema version " + std::to_string(version) +
                                 " is newer than this server understands (" + std::to_string(all.size()) + ")");
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
                throw SqliteError(SQLITE_CONSTRAINT_FOREIGNKEY,
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
