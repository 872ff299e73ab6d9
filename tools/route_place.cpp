#include "route_place.hpp"

#include <cerrno>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include "command_registry.hpp"

namespace locus::tools {

namespace {

// The whole of `s` as a positive id, or 0.
long long positive_id(const std::string& s) {
    if (s.empty() || s.size() > 18 || s.find_first_not_of("0123456789") != std::string::npos) return 0;
    return std::stoll(s);
}

bool finite_number(const std::string& s, double& out) {
    if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtod(s.c_str(), &end);
    return errno == 0 && end == s.c_str() + s.size() && std::isfinite(out);
}

}  // namespace

nlohmann::json place_json(const std::string& text, const std::string& option) {
    auto bad = [&](const std::string& why) {
        return CommandError(option + " '" + text + "' " + why + "; a place is room:ID, poi:ID or FLOOR_ID:X,Y (e.g. 3:12.5,4)");
    };
    const auto colon = text.find(':');
    if (colon == std::string::npos) throw bad("has no ':'");
    const std::string head = text.substr(0, colon), rest = text.substr(colon + 1);
    if (head == "room" || head == "poi") {
        const long long id = positive_id(rest);
        if (id <= 0) throw bad("needs a positive " + head + " id after '" + head + ":'");
        return {{head == "room" ? "room_id" : "poi_id", id}};
    }
    const long long floor = positive_id(head);
    if (floor <= 0) throw bad("starts with neither 'room', 'poi' nor a floor id");
    const auto comma = rest.find(',');
    double x = 0.0, y = 0.0;
    if (comma == std::string::npos || !finite_number(rest.substr(0, comma), x) || !finite_number(rest.substr(comma + 1), y))
        throw bad("needs X,Y in metres after the floor id");
    return {{"floor_id", floor}, {"x", x}, {"y", y}};
}

}  // namespace locus::tools
