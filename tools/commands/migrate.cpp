// `locus migrate --from sqlite:PATH --to postgresql://…`: moves a database to another backend
// (store/copy.hpp), then proves the copy by comparing every table of both. The target must be
// empty; both are migrated to this binary's schema first (the source as the server would at
// its next start).
#include <iostream>
#include <memory>

#include "command_registry.hpp"
#include "store/copy.hpp"
#include "store/migrations.hpp"

namespace locus_cli_migrate {
namespace {

using namespace locus::tools;

struct Args {
    std::string from, to;
};

std::string location_of(const std::string& url) { return url.starts_with("sqlite:") ? url.substr(7) : url; }

void run(const Args& a) {
    using namespace locus::store;
    try {
        Db from(location_of(a.from));
        Db to(location_of(a.to));
        migrate(from);
        migrate(to);
        if (!is_empty(to)) throw CommandError("the target '" + to.path() + "' already holds maps or tracks; migrate needs an empty database");
        std::size_t rows = 0;
        for (const auto& [table, n] : copy_database(from, to)) {
            if (n > 0) std::cerr << "  " << table << ": " << n << " rows\n";
            rows += static_cast<std::size_t>(n);
        }
        if (const auto diff = first_difference(from, to); !diff.empty())
            throw CommandError("the copy differs from the source: " + diff);
        std::cout << "migrated " << rows << " rows from " << from.path() << " to " << to.path() << "; every table compares equal\n";
    } catch (const DbError& e) {
        throw CommandError(e.what());
    }
}

}  // namespace

LOCUS_COMMAND("migrate", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("migrate", "Copy a database to another backend (e.g. SQLite to PostgreSQL) and verify it");
    auto args = std::make_shared<Args>();
    cmd->add_option("--from", args->from, "source: sqlite:PATH, a path, or postgresql://…")->required();
    cmd->add_option("--to", args->to, "target (must be empty): postgresql://…, sqlite:PATH or a path")->required();
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_migrate
