#pragma once
#include <string_view>
#include <vector>

#include "store/db.hpp"

namespace locus::server {
// Generated at build time from schema/NNN_*.sql (see server/embed_schema.cmake).
const std::vector<std::string_view>& migrations();
// The same numbers in PostgreSQL's dialect (schema/pg/NNN_*.sql where it differs).
const std::vector<std::string_view>& pg_migrations();
std::string_view demo_map_json();
}  // namespace locus::server

namespace locus::store {
// Applies, each in its own transaction, every migration past PRAGMA user_version (PostgreSQL:
// past the version in table locus_schema, all under one advisory lock so that servers
// starting together on an empty database migrate it once).
// Returns the resulting schema version. Refuses a database newer than this binary.
int migrate(Db& db);
}  // namespace locus::store
