#pragma once
// Why a transmitter-model request (fit.hpp, generate.hpp) cannot be done with the store as it
// is: `code` is the API's error code (docs/transmitters.md), answered 422 by http/. An unknown
// floor, radio map or transmitter is store::NotFound, as everywhere.
#include <stdexcept>
#include <string>

namespace locus::transmitters {

struct Refused : std::runtime_error {
    std::string code;
    Refused(std::string c, const std::string& message) : std::runtime_error(message), code(std::move(c)) {}
};

}  // namespace locus::transmitters
