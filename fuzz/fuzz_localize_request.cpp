// The localize request body (POST /v1/radiomaps/{id}/localize, /v1/maps/{id}/localize):
// the fast plain parser (server/http/plain_localize_request.*) and the full streaming parser
// (server/http/localize_request.*).
//
// Checks: neither parser throws anything but http::ApiError (400 or 422); whatever the plain
// parser accepts, the full parser accepts too and reads the same (algorithm, every AP's type,
// bssid and rss bit for bit, default options), as tests/unit/plain_request_test.cpp does on
// mutated bodies; parse_localize_request (the server's entry point) agrees with both.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "http/api_error.hpp"
#include "http/localize/localize_request.hpp"
#include "http/localize/plain_localize_request.hpp"
#include "json_mutator.hpp"

using namespace locus;
using namespace locus::http;

namespace {

[[noreturn]] void fail(const char* what, const std::string& body) {
    std::fprintf(stderr, "fuzz_localize_request: %s\nbody (%zu bytes): %s\n", what, body.size(), body.c_str());
    std::abort();
}

void check(bool ok, const char* what, const std::string& body) {
    if (!ok) fail(what, body);
}

// A refused body is an ApiError with a client status; anything else escapes and crashes.
template <typename Parse>
std::optional<LocalizeRequest> refused_or(Parse parse, const std::string& body) {
    try {
        return parse(body);
    } catch (const http::ApiError& e) {
        check(e.status == 400 || e.status == 422, "an ApiError with a status other than 400/422", body);
        check(!e.code.empty() && *e.what() != '\0', "an ApiError without a code or message", body);
        return std::nullopt;
    }
}

void check_request(const LocalizeRequest& r, const std::string& body) {
    check(!r.query.aps.empty(), "an accepted request without APs", body);
    for (const auto& ap : r.query.aps) {
        check(ap.type == "wifi" || ap.type == "ble", "an AP type other than wifi/ble", body);
        check(!ap.bssid.empty() && ap.bssid.size() <= 64, "a bssid outside 1..64 characters", body);
        check(std::isfinite(ap.rss) && valid_rss(ap.rss), "an rss outside [-120, 0]", body);
    }
}

void check_same(const LocalizeRequest& a, const LocalizeRequest& b, const char* what, const std::string& body) {
    check(a.algorithm == b.algorithm, what, body);
    check(a.query.aps.size() == b.query.aps.size(), what, body);
    for (std::size_t i = 0; i < a.query.aps.size(); ++i) {
        const auto& x = a.query.aps[i];
        const auto& y = b.query.aps[i];
        check(x.type == y.type && x.bssid == y.bssid && x.bssid_hash == y.bssid_hash, what, body);
        check(std::signbit(x.rss) == std::signbit(y.rss) && x.rss == y.rss, what, body);
    }
}

bool default_options(const match::Options& o) {
    const match::Options d;
    return o.k == d.k && o.candidates == d.candidates && !o.near && o.bayes_k == d.bayes_k &&
           o.tolerance == d.tolerance && o.gamma == d.gamma && o.sigma_floor == d.sigma_floor &&
           o.temperature == d.temperature && o.offset_sigma == d.offset_sigma && o.outlier_sigmas == d.outlier_sigmas &&
           o.representation == d.representation && o.distance == d.distance && o.estimate == d.estimate;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string body(reinterpret_cast<const char*>(data), size);

    const auto plain = parse_plain_localize_request(body);  // declines; never throws
    const auto full = refused_or(parse_localize_request_in_full, body);
    const auto served = refused_or(parse_localize_request, body);

    if (full) check_request(*full, body);
    check(full.has_value() == served.has_value(), "parse_localize_request and the full parser disagree on accepting", body);
    if (plain) {
        check_request(*plain, body);
        check(full.has_value(), "the plain parser accepts a body the full parser refuses", body);
        check_same(*plain, *full, "the plain and the full parser read the body differently", body);
        check(default_options(plain->options) && default_options(full->options),
              "a plain body with options other than the defaults", body);
    }
    if (served && full) check_same(*served, *full, "parse_localize_request and the full parser read the body differently", body);
    return 0;
}

LOCUS_FUZZ_JSON_MUTATOR
