#include "locus/ranging/beacon_id.hpp"

#include <cctype>

namespace locus::ranging {

namespace {
// Lower-case hex digits of `s` without its dashes, if it holds nothing else and `n` of them.
std::optional<std::string> hex_digits(std::string_view s, std::size_t n, bool dashes) {
    std::string out;
    for (char c : s) {
        if (dashes && c == '-') continue;
        if (!std::isxdigit(static_cast<unsigned char>(c))) return std::nullopt;
        out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    if (out.size() != n) return std::nullopt;
    return out;
}
}  // namespace

std::optional<std::string> ibeacon_id(std::string_view uuid, std::int64_t major, std::int64_t minor) {
    const auto hex = hex_digits(uuid, 32, true);
    if (!hex || major < 0 || major > 65535 || minor < 0 || minor > 65535) return std::nullopt;
    const std::string& h = *hex;
    return h.substr(0, 8) + "-" + h.substr(8, 4) + "-" + h.substr(12, 4) + "-" + h.substr(16, 4) + "-" + h.substr(20) + ":" +
           std::to_string(major) + ":" + std::to_string(minor);
}

std::optional<std::string> eddystone_id(std::string_view ns, std::string_view instance) {
    const auto n = hex_digits(ns, 20, false), i = hex_digits(instance, 12, false);
    if (!n || !i) return std::nullopt;
    return *n + ":" + *i;
}

}  // namespace locus::ranging
