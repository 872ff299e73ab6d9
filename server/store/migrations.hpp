#pragma once
#include <string_view>
#include <vector>

#include "store/sqlite.hpp"

namespace locus::server {
// Generated at build time from schema/NNN_*.sql (see server/embed_schema.cmake).
const std::vector<std::string_view>& migrations();
std::string_view demo_map_json();
}  // namespace locus::server

namespace locus::store {
// Applies, each in its own transaction, every migration past PRAGMA user_version.
// Returns the resulting schema version. Refuses a database newer than this binary.
int migrate(Db& db);
}  // namespace locus::store
