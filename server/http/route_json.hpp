#pragma once
// A route as POST /v1/maps/{id}/route answers it; the relative position of two tracks
// (track_routes.cpp) answers the walk between them in the same form.
#include <nlohmann/json.hpp>

#include "locus/plan/route.hpp"

namespace locus::http {

nlohmann::json route_json(const plan::Route& r);

}  // namespace locus::http
