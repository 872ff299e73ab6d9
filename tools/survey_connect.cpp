#include "survey_connect.hpp"

#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include "command_registry.hpp"

namespace locus::tools {

void ServerArgs::add_to(CLI::App& cmd) {
    cmd.add_option("--server", server, "server base URL (default: $LOCUS_SERVER, else http://127.0.0.1:8080, the server of scripts/run.sh)")
        ->envname("LOCUS_SERVER");
    cmd.add_option("--api-key", api_key, "API key for writes (default: $LOCUS_API_KEY)")->envname("LOCUS_API_KEY");
    cmd.add_option("--retries", retries, "attempts per request on network errors, 5xx and 429")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    cmd.add_option("--timeout", timeout_s, "read timeout per request, seconds")->capture_default_str()->check(CLI::PositiveNumber);
}

void add_no_progress_flag(CLI::App& cmd, bool& progress) {
    cmd.add_flag_callback("--no-progress", [&progress] { progress = false; }, "no progress bar even on a terminal");
}

void print_radiomaps(const nlohmann::json& radiomap_list) {
    for (const auto& rm : radiomap_list)
        std::fprintf(stderr, "radio map %lld '%s': %s / %s (floor id %lld)\n", rm.at("id").get<long long>(),
                     rm.at("name").get<std::string>().c_str(), rm.at("building").get<std::string>().c_str(),
                     rm.at("floor").get<std::string>().c_str(), rm.at("floor_id").get<long long>());
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

// Numbers the server formats with std::to_string ("50.000000 is outside [-120.000000,
// 0.000000]") are printed plainly: 50, -120, 0, 2.5.
std::string plain_numbers(const std::string& text) {
    static const std::regex six_decimals(R"((-?\d+)\.(\d{6})(?!\d))");
    std::string out;
    auto it = std::sregex_iterator(text.begin(), text.end(), six_decimals);
    std::size_t last = 0;
    for (; it != std::sregex_iterator(); ++it) {
        const auto& m = *it;
        out += text.substr(last, static_cast<std::size_t>(m.position()) - last);
        std::string frac = m[2].str();
        while (!frac.empty() && frac.back() == '0') frac.pop_back();
        std::string whole = m[1].str();
        if (frac.empty() && whole == "-0") whole = "0";
        out += frac.empty() ? whole : whole + "." + frac;
        last = static_cast<std::size_t>(m.position() + m.length());
    }
    return out + text.substr(last);
}

}  // namespace locus::tools
