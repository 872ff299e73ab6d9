#pragma once
// GET /v1/radiomaps/{id}/quality and POST /v1/radiomaps/{id}/tune as JSON: their query and
// body read into match::TuneLimits (ApiError on bad input), and the tuning service's results
// (tuning/service.hpp) written as the answers. Linear in the request and the answer.
#include <httplib.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "locus/match/tune.hpp"
#include "tuning/service.hpp"

namespace locus::http {

// ?folds= in [2, 50], ?max_queries= in [10, 5000]; absent ones keep TuneLimits' defaults.
match::TuneLimits parse_quality_query(const httplib::Request& req);
// {"folds", "max_queries"}, the same bounds; an empty body the defaults.
match::TuneLimits parse_tune_body(const std::string& body);

// {"radiomap_id", "settings" (with "source"), "folds", "queries", "subsampled", "mean_error_m",
// "rps": [each RP's id, name, floor, position, "error_m", "horizontal_m", "floor_ok"]}.
nlohmann::json quality_json(std::int64_t radiomap_id, const tuning::Quality& quality);
// {"radiomap_id", "settings" (the stored ones, "source": "tuned", "updated_at"), "tune": the CV table}.
nlohmann::json tuned_json(std::int64_t radiomap_id, const tuning::Tuned& tuned);

}  // namespace locus::http
