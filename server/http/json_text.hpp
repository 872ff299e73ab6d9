#pragma once
// The JSON text of a value that may hold bytes straight from the wire (a request path or
// method, an exception's message). nlohmann's dump() throws on invalid UTF-8, and a throw
// while writing an error or an access-log line would end the process; here such bytes
// become U+FFFD instead.
#include <nlohmann/json.hpp>
#include <string>

namespace locus::http {

inline std::string json_text(const nlohmann::json& j) {
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace locus::http
