#pragma once
// Every client-visible failure is an ApiError; the router turns it into
// {"error": {"code": ..., "message": ...}} with its HTTP status.
#include <cmath>
#include <stdexcept>
#include <string>

namespace locus::http {

struct ApiError : std::runtime_error {
    int status;
    std::string code;
    double retry_after_s = 0;  // > 0: answered with Retry-After, whole seconds rounded up
    ApiError(int s, std::string c, const std::string& message, double retry_after = 0)
        : std::runtime_error(message), status(s), code(std::move(c)), retry_after_s(retry_after) {}
};

// A wait as Retry-After says it: whole seconds, rounded up, at least 1 (a retry then finds
// what was missing).
inline long long retry_seconds(double wait_s) {
    const double whole = std::ceil(wait_s - 1e-9);
    return whole < 1 ? 1 : static_cast<long long>(whole);
}

inline ApiError invalid_field(const std::string& message) { return {422, "invalid_field", message}; }
// A bad query parameter (?limit=, ?q=): the request line, not a body field, is wrong.
inline ApiError invalid_query(const std::string& message) { return {400, "invalid_query", message}; }

}  // namespace locus::http
