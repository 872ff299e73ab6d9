#pragma once
// POST /v1/floors/{id}/radiomaps/generate and POST /v1/radiomaps/{id}/densify as JSON: their
// bodies read into the requests of transmitters/generate.hpp (ApiError on bad input, nothing
// read from the store), their results and refusals written as the API says
// (docs/transmitters.md). Each is linear in the body or the answer.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "http/api_error.hpp"
#include "transmitters/generate.hpp"

namespace locus::http {

// {"name", "description", "step", "min_rss", "sigma_db", "phone_height"}; "step" required.
transmitters::GenerateRequest parse_generate_request(const std::string& body, std::int64_t floor_id);
// {"step", "min_rss", "sigma_db", "phone_height"}; "step" required.
transmitters::DensifyRequest parse_densify_request(const std::string& body, std::int64_t radiomap_id);

// 422 out_of_range, naming the step and the RPs it would make.
ApiError grid_too_fine(const transmitters::GridTooFine& e);

// The imported radio map (store_json.hpp's imported_json) with "generated", "walls", "transmitters".
nlohmann::json generated_json(const transmitters::Generated& generated);
// {"radiomap_id", "surveyed_rps", "added_rps", "measurement_count", "transmitters", "walls"}.
nlohmann::json densified_json(std::int64_t radiomap_id, const transmitters::Densified& densified);

}  // namespace locus::http
