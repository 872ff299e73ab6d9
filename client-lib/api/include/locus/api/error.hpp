#pragma once
// Failures of the REST client. An ApiError is the server's answer (status, code, message);
// a NetworkError means no answer came back, after every retry was spent.
#include <stdexcept>
#include <string>

namespace locus::api {

class ApiError : public std::runtime_error {
public:
    ApiError(int status, std::string code, const std::string& message)
        : std::runtime_error(message), status_(status), code_(std::move(code)) {}
    int status() const { return status_; }
    // The server's machine-readable code, e.g. "conflict", "not_found", "invalid_field".
    const std::string& code() const { return code_; }

private:
    int status_;
    std::string code_;
};

class NetworkError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace locus::api
