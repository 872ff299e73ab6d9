#pragma once
// The localize request body and answer: {"algorithm", "scans" | "measurements", "options"}.
#include <nlohmann/json.hpp>
#include <string>

#include "locus/match/algorithm.hpp"
#include "locus/match/options.hpp"
#include "locus/match/query.hpp"
#include "localize/service.hpp"

namespace locus::localize {

// The matcher used when a request names none: the most accurate on UJIIndoorLoc, on the
// tuning users (2, 4, …, 18) and on the report users (1, 3, …, 17) alike (docs/matchers.md).
inline constexpr match::Algorithm kDefaultAlgorithm = match::Algorithm::bayes;

struct LocalizeRequest {
    match::Algorithm algorithm = kDefaultAlgorithm;
    match::Query query;
    match::Options options;
};

// Throws http::ApiError (400 invalid_json, 422 invalid_field / out_of_range) for a bad body.
// The plain body of a phone's fix takes the fast path (plain_request.hpp); every other body,
// and every bad one, is read in full by the streaming parser, which owns the error messages.
LocalizeRequest parse_localize_request(const std::string& body);
LocalizeRequest parse_localize_request_in_full(const std::string& body);

// The answer's JSON text. 422 no_match when no RP shares an AP with the scan.
std::string answer(const Snapshot& snapshot, const LocalizeRequest& request);

// Fills snapshot.candidate_json from its index, so an answer writes only each candidate's
// score and matched APs: formatting the ten candidates' coordinates and ids anew was a quarter
// of a one-floor localize request's own work. An answer without it writes every field.
void prepare_answers(Snapshot& snapshot);

}  // namespace locus::localize
