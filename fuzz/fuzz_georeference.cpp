// A floor's georeference by control points (POST /v1/floors/{id}/georeference): the body through
// parse_control_points, then the fit and what the route stores, as server/http/plans/geo_routes.cpp
// does (kept in step with it by hand); and the same body's "geo", if any, through a floor PATCH's
// validation.
//
// Checks: nothing but http::ApiError (400/422) escapes; accepted points are 3 to 1000, finite and
// in range; a fit is either refused with a problem or gives a georeference inside the ranges a
// PATCH accepts (so what the route stores always reads back), finite residuals (one per point),
// RMS and a positive scale.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "http/api_error.hpp"
#include "http/plans/georeference_request.hpp"
#include "http/validation.hpp"
#include "json_mutator.hpp"
#include "store/kinds.hpp"

using namespace locus;
using nlohmann::json;

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail, const std::string& body) {
    std::fprintf(stderr, "fuzz_georeference: %s %s\nbody (%zu bytes): %s\n", what, detail.c_str(), body.size(), body.c_str());
    std::abort();
}

void check_patch_geo(const std::string& body) {
    const json j = json::parse(body, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("geo")) return;
    try {
        (void)http::validated_fields(store::kind("floors"), json{{"geo", j.at("geo")}}, false);
    } catch (const http::ApiError& e) {
        if (e.status != 422) fail("a PATCH geo ApiError with status", std::to_string(e.status), body);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string body(reinterpret_cast<const char*>(data), size);
    check_patch_geo(body);
    std::vector<geo::ControlPoint> points;
    try {
        points = http::parse_control_points(body);
    } catch (const http::ApiError& e) {
        if (e.status != 400 && e.status != 422) fail("an ApiError with status", std::to_string(e.status), body);
        return 0;
    }
    if (points.size() < 3 || points.size() > http::kMaxControlPoints) fail("a point count of", std::to_string(points.size()), body);
    for (const auto& p : points)
        if (!std::isfinite(p.floor.x) || !std::isfinite(p.floor.y) || !(std::fabs(p.earth.lat) <= 90) ||
            !(std::fabs(p.earth.lon) <= 180))
            fail("a point out of range", "", body);
    const auto r = geo::fit_georeference(points);
    if (!r.fit) {
        if (!r.problem) fail("no fit and no problem", "", body);
        return 0;
    }
    const auto& f = *r.fit;
    // What the route stores, as a PATCH would have to accept it.
    const json stored = {{"geo", http::georeference_json(f.georeference)}};
    try {
        (void)http::validated_fields(store::kind("floors"), stored, false);
    } catch (const http::ApiError& e) {
        fail("a stored georeference a PATCH refuses:", stored.dump() + " (" + e.what() + ")", body);
    }
    if (!(f.georeference.bearing_deg >= 0 && f.georeference.bearing_deg < 360)) fail("a bearing of", std::to_string(f.georeference.bearing_deg), body);
    if (f.residuals_m.size() != points.size()) fail("residuals for", std::to_string(f.residuals_m.size()), body);
    for (double res : f.residuals_m)
        if (!std::isfinite(res) || res < 0) fail("a residual of", std::to_string(res), body);
    if (!std::isfinite(f.rms_m) || !std::isfinite(f.scale) || !(f.scale > 0)) fail("an rms or scale of", std::to_string(f.rms_m) + " " + std::to_string(f.scale), body);
    return 0;
}

LOCUS_FUZZ_JSON_MUTATOR
