#include "survey_connect.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "command_registry.hpp"

namespace locus::tools {

void ServerArgs::add_to(CLI::App& cmd, bool server_required) {
    auto* s = cmd.add_option("--server", server, "server base URL, e.g. http://127.0.0.1:8080");
    if (server_required) s->required();
    cmd.add_option("--api-key", api_key, "API key for writes (default: $LOCUS_API_KEY)")->envname("LOCUS_API_KEY");
    cmd.add_option("--retries", retries, "attempts per request on network errors, 5xx and 429")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    cmd.add_option("--timeout", timeout_s, "read timeout per request, seconds")->capture_default_str()->check(CLI::PositiveNumber);
}

api::ClientOptions ServerArgs::client_options() const {
    api::ClientOptions o;
    o.base_url = server;
    while (!o.base_url.empty() && o.base_url.back() == '/') o.base_url.pop_back();
    o.api_key = api_key;
    o.retry.max_attempts = retries;
    o.read_timeout = std::chrono::milliseconds(static_cast<long long>(timeout_s * 1000.0));
    return o;
}

std::string fingerprint(std::string_view bytes) {
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ull;
    }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw CommandError("cannot read '" + path + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace locus::tools
