#pragma once
// Storing a floor's plan with every check the API promises: check_plan on the plan itself,
// then, inside the store's transaction, its links against the map's other plans. PUT
// /v1/floors/{id}/plan and the demo map's plans (locus-server --demo) both write through it.
#include <cstdint>

#include "locus/plan/plan.hpp"
#include "store/store.hpp"

namespace locus::http {

// Throws ApiError 422 invalid_plan listing the problems (each naming its feature) and writes
// nothing; store::NotFound for an unknown floor.
store::StoredPlan put_checked_plan(store::Store& store, std::int64_t floor_id, const plan::Plan& plan);

}  // namespace locus::http
