#pragma once
// The fast path of the localize request parser, for the body a phone sends on every fix:
//
//   {"algorithm": "bayes", "scans": [[{"bssid": "..", "rss": -61, "type": "wifi"}, ..], ..]}
//
// (keys in any order, "algorithm" and "type" optional). Why: nlohmann's lexer keeps a copy of
// every token for its error messages and costs ~8 µs on a 600-byte scan, half of a radio-map
// localize request's own work, and `locus bench localize` showed throughput tracking it.
//
// It is not a second parser with its own rules: it accepts only bodies it can read with
// certainty and declines everything else (escapes, non-ASCII text, "options", "measurements",
// null, duplicate keys, any value out of range, any syntax it does not expect), and a declined
// body goes through the full parser (localize_request.cpp), which owns every error message. So for a
// body it accepts, the result is what the full parser gives (tests/unit/plain_request_test.cpp
// checks this on real scans and on thousands of mutated bodies).
#include <optional>
#include <string_view>

#include "http/localize/localize_request.hpp"

namespace locus::http {

std::optional<LocalizeRequest> parse_plain_localize_request(std::string_view body);

}  // namespace locus::http
