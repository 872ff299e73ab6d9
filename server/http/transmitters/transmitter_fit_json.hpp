#pragma once
// POST /v1/floors/{id}/transmitters/fit as JSON: the request's ?apply= and body read into a
// transmitters::FitRequest (ApiError on bad input, nothing read from the store), and the
// FitResult written as the answer. Both are linear in the body and the answer.
#include <httplib.h>

#include <cstdint>
#include <nlohmann/json.hpp>

#include "transmitters/fit.hpp"

namespace locus::http {

// ?apply=true|false; body {"min_rps", "refit_positions", "phone_height", "transmitters": [ids]},
// all optional, an empty body the defaults.
transmitters::FitRequest parse_fit_request(const httplib::Request& req, std::int64_t floor_id);

// {"floor_id", "rps", "applied", "transmitters": [...], "skipped": [...]}.
nlohmann::json fit_json(std::int64_t floor_id, const transmitters::FitResult& result);

}  // namespace locus::http
