#pragma once
// The localize request body: {"algorithm", "scans" | "measurements", "options"}.
#include <nlohmann/json.hpp>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "locus/match/algorithm.hpp"
#include "locus/match/options.hpp"
#include "locus/match/query.hpp"
#include "locus/match/tune.hpp"

namespace locus::http {

// The matcher used when a request names none (chosen in locus/match/algorithm.hpp, where
// `locus eval` reads it too).
inline constexpr match::Algorithm kDefaultAlgorithm = match::kDefaultAlgorithm;

// A localize body holds at most this many scans, and a scan (or the measurements) at most
// this many readings: checked while parsing, which stops at the first one past them (422
// out_of_range), so `{"scans": [[], [], …]}` is not read into millions of empty scans.
inline constexpr std::size_t kMaxScans = 1000;
inline constexpr std::size_t kMaxReadings = 10'000;

struct LocalizeRequest {
    match::Algorithm algorithm = kDefaultAlgorithm;  // as named, else the built-in default
    match::Query query;
    match::Options options;  // as sent, over the built-in defaults
    bool algorithm_given = false;
    nlohmann::json options_given;  // the "options" object as sent (checked); null: none
    // "track_id": match in that live track's subarea (POST /v1/maps/{id}/localize, with the
    // track's token; docs/tracks.md "Subarea"). The route resolves it into track_subarea:
    // none when the track has no fix yet or its subarea is off (the whole map answers).
    std::optional<std::int64_t> track_id;
    std::optional<match::Near> track_subarea;
};

// What the request runs with on an index whose radio map stores `defaults`: whatever the
// request does not specify comes from them. The stored options are the base only when the
// request names no algorithm or the stored one (a radio map tuned to wknn k=5 says nothing
// about bayes's k); the request's own options go on top.
match::Setting resolve(const LocalizeRequest& request, const match::Setting& defaults);

// The "options" object over `base` (422 for an unknown or bad member). `where` names it.
match::Options parse_options(const nlohmann::json& j, match::Options base, const std::string& where = "options");

// Throws ApiError (400 invalid_json, 422 invalid_field / out_of_range) for a bad body.
// The plain body of a phone's fix takes the fast path (plain_localize_request.hpp); every
// other body, and every bad one, is read in full by the streaming parser, which owns the
// error messages.
LocalizeRequest parse_localize_request(const std::string& body);
LocalizeRequest parse_localize_request_in_full(const std::string& body);

}  // namespace locus::http
