#include "startup/checks.hpp"

#include <filesystem>
#include <system_error>

#include "store/db.hpp"

namespace locus::startup {

bool is_loopback_host(const std::string& host) {
    return host == "localhost" || host == "::1" || host == "[::1]" || host.starts_with("127.");
}

std::optional<std::string> open_writes_problem(const std::string& host, bool has_api_key, bool allow_open_writes) {
    if (has_api_key || allow_open_writes || is_loopback_host(host)) return std::nullopt;
    return "refusing to listen on " + host +
           " without an API key: anyone who reaches it could change or delete every map. Set --api-key (or "
           "LOCUS_API_KEY), listen on 127.0.0.1, or pass --allow-open-writes if the network in front is yours";
}

std::optional<std::string> database_path_problem(const std::string& db) {
    if (store::is_postgres_url(db)) return std::nullopt;
    const std::filesystem::path path(db.starts_with("sqlite:") ? db.substr(7) : db);
    const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    std::error_code ec;
    if (std::filesystem::is_directory(dir, ec)) return std::nullopt;
    if (std::filesystem::exists(dir, ec))
        return "cannot create the database '" + path.string() + "': '" + dir.string() + "' is not a directory";
    return "cannot create the database '" + path.string() + "': its directory '" + dir.string() +
           "' does not exist; create it (mkdir -p " + dir.string() + ") or pass another --db";
}

std::string listen_problem(const std::string& error) {
    if (error.find("Address already in use") != std::string::npos)
        return error + ": another process (another locus-server?) listens there; stop it, or pass another --port";
    if (error.find("Permission denied") != std::string::npos)
        return error + ": ports below 1024 need privileges; pass a --port of 1024 or more";
    return error;
}

}  // namespace locus::startup
