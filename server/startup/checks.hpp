#pragma once
// What the server checks before it opens its database or port, so that a mistake in the
// flags is one clear line with what to do, not a stack of errors or, worse, a server that
// runs as it should not (docs/deploy.md, "Single node").
#include <optional>
#include <string>

namespace locus::startup {

// True for an address only this machine can reach: 127.0.0.0/8, ::1, localhost.
bool is_loopback_host(const std::string& host);

// Why the server must not listen on `host` with these settings, or nullopt: without an API key
// every write is open to whoever reaches the port, which beyond loopback is the network, so
// that takes `--allow-open-writes` said out loud.
std::optional<std::string> open_writes_problem(const std::string& host, bool has_api_key, bool allow_open_writes);

// Why an SQLite database at `db` (a path or sqlite:PATH; a PostgreSQL URL is not checked)
// cannot be created, or nullopt: its directory does not exist. Reads the file system only.
std::optional<std::string> database_path_problem(const std::string& db);

// The one line said when binding the port failed, with what to do about it.
std::string listen_problem(const std::string& error);

}  // namespace locus::startup
