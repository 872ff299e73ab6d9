// `locus backup --db PATH --out FILE [--force]`: a consistent copy of a server's SQLite database
// while the server keeps running, through SQLite's online backup API. The copy is written to a
// temporary name beside FILE, checked (integrity_check, and the schema version equals the
// source's) and only then renamed to FILE, so FILE is either the old file or a whole, checked
// copy: never half written. A PostgreSQL URL is refused with the tool to use (pg_dump), exit 2.
#include <sqlite3.h>
#include <unistd.h>
#include <fcntl.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "command_registry.hpp"

namespace locus_cli_backup {
namespace {

using namespace locus::tools;
namespace fs = std::filesystem;

struct Args {
    std::string db;
    std::string out;
    bool force = false;
};

struct Closer {
    void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
using Db = std::unique_ptr<sqlite3, Closer>;

std::string message_of(sqlite3* db) { return db ? sqlite3_errmsg(db) : "out of memory"; }

Db open(const std::string& path, int flags, const std::string& what) {
    sqlite3* raw = nullptr;
    const int rc = sqlite3_open_v2(path.c_str(), &raw, flags, nullptr);
    Db db(raw);
    if (rc != SQLITE_OK) throw CommandError("cannot open " + what + " '" + path + "': " + message_of(raw));
    // The server may hold the write lock for a moment (a checkpoint); wait for it, not fail.
    sqlite3_busy_timeout(raw, 10000);
    return db;
}

// One row, one column: PRAGMA answers.
std::string single(sqlite3* db, const char* sql, const std::string& what) {
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db, sql, -1, &raw, nullptr) != SQLITE_OK)
        throw CommandError(what + ": " + message_of(db));
    std::unique_ptr<sqlite3_stmt, int (*)(sqlite3_stmt*)> stmt(raw, sqlite3_finalize);
    const int rc = sqlite3_step(raw);
    if (rc != SQLITE_ROW) throw CommandError(what + ": " + message_of(db));
    const auto* text = sqlite3_column_text(raw, 0);
    return text ? reinterpret_cast<const char*>(text) : "";
}

// The database file and the journals SQLite may leave beside it.
void remove_with_journals(const std::string& path) {
    std::error_code ignored;
    for (const char* suffix : {"", "-journal", "-wal", "-shm"}) fs::remove(path + suffix, ignored);
}

// The rename is durable only once the directory entry is on disk too.
void sync_directory(const fs::path& dir) {
    const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

bool is_postgres_url(const std::string& s) { return s.starts_with("postgresql://") || s.starts_with("postgres://"); }

void run(const Args& a) {
    if (is_postgres_url(a.db))
        throw CommandError("'" + a.db.substr(0, a.db.find("://") + 3) +
                               "…' is a PostgreSQL database: back it up with PostgreSQL's own tool, e.g. "
                               "pg_dump --format=custom --file=locus.dump '<url>' (docs/deploy.md, Backups)",
                           2);
    const std::string source = a.db.starts_with("sqlite:") ? a.db.substr(7) : a.db;
    std::error_code ec;
    if (!fs::is_regular_file(source, ec)) throw CommandError("no database file at '" + source + "'");

    const fs::path out(a.out);
    const fs::path dir = out.parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw CommandError("cannot write '" + a.out + "': directory '" + dir.string() + "' does not exist");
    if (fs::exists(out, ec)) {
        if (fs::equivalent(out, source, ec))
            throw CommandError("'" + a.out + "' is the database itself: back it up to another file");
        if (!a.force) throw CommandError("'" + a.out + "' already exists; pass --force to replace it");
        if (!fs::is_regular_file(out, ec)) throw CommandError("'" + a.out + "' is not a regular file; not replacing it");
    }

    // Read-only: a backup never changes the server's database. In WAL mode a reader neither
    // waits for the server's writes nor holds them up.
    const Db src = open(source, SQLITE_OPEN_READONLY, "database");
    const std::string version = single(src.get(), "PRAGMA user_version", "'" + source + "' is not a Locus database");
    if (version == "0") throw CommandError("'" + source + "' is not a Locus database (no schema version)");

    const std::string temp = a.out + ".partial-" + std::to_string(::getpid());
    remove_with_journals(temp);
    struct Cleanup {
        std::string path;
        bool armed = true;
        ~Cleanup() {
            if (armed) remove_with_journals(path);
        }
    } cleanup{temp};
    std::string summary;
    {
        Db dst = open(temp, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, "backup file");
        sqlite3_backup* backup = sqlite3_backup_init(dst.get(), "main", src.get(), "main");
        if (!backup) throw CommandError("cannot start the backup to '" + temp + "': " + message_of(dst.get()));
        // All pages in one step: one read transaction, so the copy is the database as of one
        // commit. Copying in slices would restart from the first page whenever the server
        // commits in between, and under steady uploads might never finish.
        int rc = SQLITE_OK;
        for (int tries = 0; tries < 100; ++tries) {
            rc = sqlite3_backup_step(backup, -1);
            if (rc != SQLITE_BUSY && rc != SQLITE_LOCKED) break;
            sqlite3_sleep(100);
        }
        const int pages = sqlite3_backup_pagecount(backup);
        const int finish = sqlite3_backup_finish(backup);
        if (rc != SQLITE_DONE || finish != SQLITE_OK)
            throw CommandError("backup of '" + source + "' to '" + temp + "' failed: " + message_of(dst.get()));

        const std::string integrity = single(dst.get(), "PRAGMA integrity_check", "checking the copy");
        if (integrity != "ok") throw CommandError("the copy fails PRAGMA integrity_check: " + integrity);
        const std::string copied = single(dst.get(), "PRAGMA user_version", "reading the copy's schema version");
        if (copied != version)
            throw CommandError("the copy's schema version " + copied + " differs from the database's " + version +
                               " (was the server upgraded during the backup? run it again)");
        // One self-contained file (no -wal beside it) that can be moved or archived alone; the
        // server switches it back to WAL when it opens it.
        single(dst.get(), "PRAGMA journal_mode=DELETE", "finishing the copy");
        summary = "backed up '" + source + "' (schema version " + version + ", " + std::to_string(pages) +
                  " pages) to '" + a.out + "'; integrity check ok";
    }
    fs::rename(temp, out, ec);
    if (ec) throw CommandError("cannot rename '" + temp + "' to '" + a.out + "': " + ec.message());
    cleanup.armed = false;
    sync_directory(out.parent_path());
    std::cout << summary << "\n";
}

}  // namespace

LOCUS_COMMAND("backup", [](CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "backup", "Copy a server's SQLite database while it runs (online backup), checked, to a new file");
    auto args = std::make_shared<Args>();
    cmd->add_option("--db", args->db, "the server's database: PATH or sqlite:PATH (PostgreSQL: use pg_dump)")
        ->required();
    cmd->add_option("--out,-o", args->out, "file to write; refused if it exists, unless --force")->required();
    cmd->add_flag("--force", args->force, "replace FILE if it exists");
    cmd->callback([args] { run(*args); });
});

}  // namespace locus_cli_backup
