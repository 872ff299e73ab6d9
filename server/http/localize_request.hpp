#pragma once
// The localize request body: {"algorithm", "scans" | "measurements", "options"}.
#include <optional>
#include <string>

#include "locus/match/algorithm.hpp"
#include "locus/match/options.hpp"
#include "locus/match/query.hpp"

namespace locus::http {

// The matcher used when a request names none (chosen in locus/match/algorithm.hpp, where
// `locus eval` reads it too).
inline constexpr match::Algorithm kDefaultAlgorithm = match::kDefaultAlgorithm;

struct LocalizeRequest {
    match::Algorithm algorithm = kDefaultAlgorithm;
    match::Query query;
    match::Options options;
};

// Throws ApiError (400 invalid_json, 422 invalid_field / out_of_range) for a bad body.
// The plain body of a phone's fix takes the fast path (plain_localize_request.hpp); every
// other body, and every bad one, is read in full by the streaming parser, which owns the
// error messages.
LocalizeRequest parse_localize_request(const std::string& body);
LocalizeRequest parse_localize_request_in_full(const std::string& body);

}  // namespace locus::http
