#pragma once
// The options every command that talks to the server shares (--server, --api-key, --retries,
// --timeout), turned into a REST client configuration. LOCUS_API_KEY is read when
// --api-key is not given.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "locus/api/client.hpp"

namespace locus::tools {

struct ServerArgs {
    std::string server = "http://127.0.0.1:8080";
    std::string api_key;
    int retries = 6;
    double timeout_s = 30.0;

    // --server (every command alike: $LOCUS_SERVER, else this default), --api-key
    // ($LOCUS_API_KEY), --retries, --timeout.
    void add_to(CLI::App& cmd);
    api::ClientOptions client_options() const;
};

// --no-progress: turns `progress` off. Declared as a plain flag with a callback, so --help
// shows "--no-progress", not the negated "!--no-progress" form's "--no-progress{false}".
void add_no_progress_flag(CLI::App& cmd, bool& progress);

// An import's radio maps on stderr, one line each, so the ids to use next are in sight:
// "radio map 5 'UJIIndoorLoc building 1 floor 0': Building 1 / Floor 0 (floor id 5)".
// Each item has id, name, building, floor, floor_id (an import summary's radiomap_list).
void print_radiomaps(const nlohmann::json& radiomap_list);

// Content fingerprint used to derive per-file upload ids (FNV-1a 64, hex).
std::string fingerprint(std::string_view bytes);
std::string read_file(const std::string& path);

// Numbers formatted with std::to_string (the server's "'rss' = 50.000000 is outside
// [-120.000000, 0.000000]") printed plainly: "50 is outside [-120, 0]"; 2.500000 -> 2.5.
std::string plain_numbers(const std::string& text);

}  // namespace locus::tools
