#pragma once
// The options every command that talks to the server shares (--server, --api-key, --retries,
// --timeout), turned into a REST client configuration. LOCUS_API_KEY is read when
// --api-key is not given.
#include <CLI/CLI.hpp>
#include <string>

#include "locus/api/client.hpp"

namespace locus::tools {

struct ServerArgs {
    std::string server = "http://127.0.0.1:8080";
    std::string api_key;
    int retries = 6;
    double timeout_s = 30.0;

    void add_to(CLI::App& cmd, bool server_required = true);
    api::ClientOptions client_options() const;
};

// Content fingerprint used to derive per-file upload ids (FNV-1a 64, hex).
std::string fingerprint(std::string_view bytes);
std::string read_file(const std::string& path);

}  // namespace locus::tools
