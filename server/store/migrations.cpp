#include "store/migrations.hpp"

#include <string>

namespace locus::store {

int migrate(Db& db) {
    const auto& all = server::migrations();
    Stmt q(db, "PRAGMA user_version");
    q.step();
    int version = static_cast<int>(q.int64(0));
    if (version > static_cast<int>(all.size()))
        throw SqliteError(0, "database schema version " + std::to_string(version) +
                                 " is newer than this server understands (" + std::to_string(all.size()) + ")");
    for (auto i = static_cast<std::size_t>(version); i < all.size(); ++i) {
        Transaction tx(db);
        db.exec(all[i]);
        db.exec("PRAGMA user_version = " + std::to_string(i + 1));
        tx.commit();
        version = static_cast<int>(i + 1);
    }
    return version;
}

}  // namespace locus::store
