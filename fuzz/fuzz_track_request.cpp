// The track routes' bodies (server/http/track_request.*): POST /v1/tracks, …/fixes and …/steps.
//
// Checks: no reader throws anything but http::ApiError (400, 413 or 422, with a code and a
// message); what one accepts is as docs/tracks.md promises: a positive map id, a label of at
// most 100 characters and fusion options only for the Kalman methods; at most
// kMaxFixesPerRequest items, at least one for the steps; every list in time order, every
// number finite and in its range (headings in [0, 360), step lengths in [0, 3] m, accuracies
// in [0, 10 000] m), every fix on a positive floor id, every scan with readings, every pressure in
// [300, 1200] hPa and at most kMaxPressurePerRequest of them, every GNSS fix's latitude in
// [-90, 90], longitude in [-180, 180] and accuracy in (0, 10 000] m, at most kMaxGnssPerRequest.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "http/api_error.hpp"
#include "http/tracks/track_request.hpp"
#include "http/validation.hpp"
#include "json_mutator.hpp"

using namespace locus;
using namespace locus::http;

namespace {

// Fixes of any age are taken: the corpus's timestamps do not go stale.
constexpr double kRetentionS = 1e12;

[[noreturn]] void fail(const char* what, const std::string& body) {
    std::fprintf(stderr, "fuzz_track_request: %s\nbody (%zu bytes): %s\n", what, body.size(), body.c_str());
    std::abort();
}

void check(bool ok, const char* what, const std::string& body) {
    if (!ok) fail(what, body);
}

template <typename Parse>
void refused_or(Parse parse, const std::string& body) {
    try {
        parse();
    } catch (const http::ApiError& e) {
        check(e.status == 400 || e.status == 413 || e.status == 422, "an ApiError with a status other than 400/413/422", body);
        check(!e.code.empty() && *e.what() != '\0', "an ApiError without a code or message", body);
    }
}

bool heading_ok(double h) { return std::isfinite(h) && h >= 0 && h < 360; }

void check_fix(const tracks::Fix& f, const std::string& body) {
    check(std::isfinite(f.t) && std::isfinite(f.x) && std::isfinite(f.y), "a fix with a number that is not finite", body);
    check(f.floor_id > 0, "a fix on a floor id that is not positive", body);
    check(f.accuracy_m >= 0 && f.accuracy_m <= 10'000, "a fix's accuracy_m outside [0, 10000]", body);
    check(!f.heading_deg || heading_ok(*f.heading_deg), "a fix's heading outside [0, 360)", body);
}

template <typename T>
void check_in_time_order(const std::vector<T>& items, const std::string& body) {
    check(std::is_sorted(items.begin(), items.end(), [](const T& a, const T& b) { return a.t < b.t; }), "a list out of time order", body);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string body(reinterpret_cast<const char*>(data), size);

    refused_or([&] {
        const auto open = parse_open_request(parse_object(body));
        check(open.map_id > 0, "an open request with a map id that is not positive", body);
        check(open.label.size() <= 400, "an open request with a label over 100 characters", body);  // UTF-8: up to 4 bytes each
        // Every option set is one the method takes (tracks/fusion_options.hpp), within its range.
        for (const auto& spec : tracks::kFusionOptions) {
            const std::optional<double>& v = open.fusion_options.*spec.field;
            if (!v) continue;
            check(tracks::takes(spec, open.fusion), "a fusion option the track's method does not take", body);
            check(std::isfinite(*v) && *v >= spec.min && *v <= spec.max, "a fusion option outside its range", body);
        }
    }, body);

    refused_or([&] {
        const auto fixes = parse_fixes(parse_object(body), kRetentionS);
        check(!fixes.empty() && fixes.size() <= kMaxFixesPerRequest, "a fixes batch of a size outside 1..1000", body);
        for (const auto& f : fixes) check_fix(f, body);
        check_in_time_order(fixes, body);
    }, body);

    refused_or([&] {
        const auto in = parse_steps_request(parse_object(body), kRetentionS);
        const std::size_t n = in.steps.size() + in.fixes.size() + in.scans.size();
        check(n + in.pressure.size() + in.gnss.size() >= 1 && n <= kMaxFixesPerRequest, "a steps batch of a size outside 1..1000", body);
        check(in.pressure.size() <= kMaxPressurePerRequest, "more pressure samples than a request takes", body);
        for (const auto& p : in.pressure)
            check(std::isfinite(p.t) && p.hpa >= kMinPressureHpa && p.hpa <= kMaxPressureHpa, "a pressure outside [300, 1200] hPa", body);
        check(in.gnss.size() <= kMaxGnssPerRequest, "more GNSS fixes than a request takes", body);
        for (const auto& g : in.gnss) {
            check(std::isfinite(g.t) && g.lat >= -90 && g.lat <= 90 && g.lon >= -180 && g.lon <= 180, "a GNSS fix off the Earth", body);
            check(g.accuracy_m > 0 && g.accuracy_m <= kMaxGnssAccuracyM, "a GNSS fix's accuracy_m outside (0, 10000]", body);
        }
        for (const auto& s : in.steps) {
            check(std::isfinite(s.t) && s.length_m >= 0 && s.length_m <= 3, "a step's length outside [0, 3] m", body);
            check(heading_ok(s.heading_deg), "a step's heading outside [0, 360)", body);
        }
        for (const auto& f : in.fixes) check_fix(f, body);
        for (const auto& s : in.scans) check(!s.readings.empty() && !s.where.empty(), "a scan without readings or a name", body);
        check_in_time_order(in.steps, body);
        check_in_time_order(in.fixes, body);
        check_in_time_order(in.scans, body);
        check_in_time_order(in.pressure, body);
        check_in_time_order(in.gnss, body);
    }, body);
    return 0;
}

LOCUS_FUZZ_JSON_MUTATOR
