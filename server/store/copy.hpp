#pragma once
// Moving a database from one backend to another (`locus migrate --from sqlite:PATH --to
// postgresql://…`): every row of every table, ids included (clients hold them), and each
// identity sequence set past the largest id ever handed out, so ids stay never reused.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "store/db.hpp"

namespace locus::store {

// The tables that hold data, parents before children (ready_probe and change_counter hold none).
const std::vector<std::string>& data_tables();

// True when `db` holds no map and no track (a target must be empty).
bool is_empty(Db& db);

// Copies every data table of `from` into `to` in one transaction on `to` (both migrated to this
// binary's schema). Returns the rows copied per table.
std::vector<std::pair<std::string, std::int64_t>> copy_database(Db& from, Db& to);

// The first row where the two databases differ ("table rps, row 3: …"), or empty when every
// data table holds the same rows with the same values.
std::string first_difference(Db& a, Db& b);

}  // namespace locus::store
