#pragma once
// Request-body validation: everything a handler hands to the store or the matchers has
// passed through here, so the layers below can assume well-formed, finite, in-range input.
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "locus/radio_map.hpp"
#include "http/api_error.hpp"
#include "store/documents.hpp"
#include "store/kinds.hpp"

namespace locus::http {

// Parses a request body that must be a JSON object (400 invalid_json otherwise).
nlohmann::json parse_object(const std::string& body);
// 400 invalid_json for a body holding a NUL byte: nlohmann's lexer takes NUL for the end of
// the input, so '{"a":1}' followed by NUL and anything at all would otherwise parse.
void reject_nul(std::string_view body);
// 400 invalid_json for a body nesting arrays and objects deeper than kMaxJsonDepth, found by
// one pass over the text before any tree is built: each level of `[[[[…` costs some 70 bytes
// of tree for one byte of text. No request of this API nests half as deep (a GeoJSON
// MultiPolygon's coordinates are 6 levels into a plan).
constexpr std::size_t kMaxJsonDepth = 64;
void reject_deep(std::string_view body);

// Checks a create (all required fields present) or a patch (any subset) against the kind's
// fields; unknown fields are refused so that a typo never silently drops data. Returns the
// accepted values, typed (with the rectangles for rooms).
store::Fields validated_fields(const store::Kind& kind, const nlohmann::json& body, bool create);

// Path ids: a positive 64-bit integer, else 404 (no such resource can exist).
std::int64_t parse_id(std::string_view text, std::string_view what);

struct Page {
    std::int64_t limit = 100;
    std::int64_t offset = 0;
};
inline constexpr std::int64_t kMaxPageLimit = 1000;
Page parse_page(const std::optional<std::string>& limit, const std::optional<std::string>& offset);
// A query parameter that must be an integer in [lo, hi] (400 invalid_query naming it otherwise).
std::int64_t parse_query_integer(const std::string& text, const char* name, std::int64_t lo, std::int64_t hi);

// Refuses any key of object `j` not in `allowed` (422 "unknown field 'where.key'").
void only_fields(const nlohmann::json& j, std::initializer_list<std::string_view> allowed, const std::string& where);

// Scan and measurement bodies. `where` names the place in the body for error messages.
Reading parse_reading(const nlohmann::json& j, const std::string& where);
std::vector<Scan> parse_scans(const nlohmann::json& j, const std::string& where);
Measurement parse_measurement(const nlohmann::json& j, const std::string& where);
std::vector<Measurement> parse_measurements(const nlohmann::json& j, const std::string& where);

// The body of POST /v1/rps/{id}/scans: raw scans (aggregated here) or aggregates (two of one AP
// combine like two uploads). Throws ApiError (400, 422) for anything the store must not see.
store::ScanBatch parse_scan_upload(const std::string& body);

// A number field that must be finite (and within [min, max] when given).
double finite_number(const nlohmann::json& obj, std::string_view field, const std::string& where,
                     std::optional<double> min = std::nullopt, std::optional<double> max = std::nullopt);
std::optional<std::string> optional_string(const nlohmann::json& obj, std::string_view field,
                                           const std::string& where, std::size_t max_length = 256);

// Problems with one reading's values, shared by the JSON-tree validators here and the
// streaming localize parser: nullptr when fine, else what is wrong ("must be ..."), for the
// caller to word with the field's place (so the happy path builds no strings).
const char* type_problem(std::string_view type);
const char* bssid_problem(std::string_view raw);  // the raw value, before it becomes a Bssid
// 422 out_of_range naming the field, its value and the bounds.
ApiError out_of_range(const std::string& name, double value, std::optional<double> min, std::optional<double> max);

// The radio-map exchange document accepted by import (and produced by export), validated and
// typed; its BSSIDs normalised.
store::RadioMapDocument parse_radiomap_document(const nlohmann::json& doc);

}  // namespace locus::http
