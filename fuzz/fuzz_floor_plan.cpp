// A floor plan body (PUT /v1/floors/{id}/plan): parse_object, then parse_plan and the links
// check, as the handler in server/http/plans/plan_routes.cpp does.
//
// Checks: nothing but http::ApiError (400/422) escapes, and a 422 is invalid_plan; an
// accepted plan written back as the server answers it (plan_json) reads back to the same
// plan, so what a client GETs it can always PUT again unchanged.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "http/api_error.hpp"
#include "http/json_text.hpp"
#include "http/plans/plan_json.hpp"
#include "http/validation.hpp"
#include "json_mutator.hpp"

using namespace locus;
using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& what, const std::string& body) {
    std::fprintf(stderr, "fuzz_floor_plan: %s\nbody (%zu bytes): %s\n", what.c_str(), body.size(), body.c_str());
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string body(reinterpret_cast<const char*>(data), size);
    plan::Plan parsed;
    try {
        parsed = http::parse_plan(http::parse_object(body));
        // Floor 1 of a map whose floor 2 has no plan yet: links there are kept, others refused.
        (void)plan::link_problems(1, parsed, {{2, nullptr}});
    } catch (const http::ApiError& e) {
        if (e.status != 400 && e.status != 422) fail("an ApiError with status " + std::to_string(e.status), body);
        if (e.status == 422 && e.code != "invalid_plan") fail("a 422 with code " + e.code, body);
        return 0;
    }
    store::StoredPlan stored;
    stored.floor_id = 1;
    stored.version = 1;
    stored.plan = parsed;
    const json written = http::plan_json(stored);
    json again;
    try {
        again = http::plan_json({1, http::parse_plan(http::parse_object(http::json_text(written))), 1, ""});
    } catch (const http::ApiError& e) {
        fail(std::string("the answer of an accepted plan does not parse: ") + e.what(), body);
    }
    again["updated_at"] = written.at("updated_at");
    if (again != written) fail("plan -> GeoJSON -> plan changed it:\n" + http::json_text(written) + "\n" + http::json_text(again), body);
    return 0;
}

LOCUS_FUZZ_JSON_MUTATOR
