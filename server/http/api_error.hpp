#pragma once
// Every client-visible failure is an ApiError; the router turns it into
// {"error": {"code": ..., "message": ...}} with its HTTP status.
#include <stdexcept>
#include <string>

namespace locus::http {

struct ApiError : std::runtime_error {
    int status;
    std::string code;
    ApiError(int s, std::string c, const std::string& message)
        : std::runtime_error(message), status(s), code(std::move(c)) {}
};

inline ApiError invalid_field(const std::string& message) { return {422, "invalid_field", message}; }
// A bad query parameter (?limit=, ?q=): the request line, not a body field, is wrong.
inline ApiError invalid_query(const std::string& message) { return {400, "invalid_query", message}; }

}  // namespace locus::http
