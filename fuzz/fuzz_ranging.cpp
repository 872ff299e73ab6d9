// The ranging side of the localize body ("algorithm": "trilateration" | "multilateration" |
// "proximity", server/http/localize/ranging_localize.*) and a transmitter's body
// (server/http/transmitter_fields.*), then trilateration, multilateration and the nearest
// transmitter on the parsed scan, each AP placed by its bssid's hash.
//
// Checks: the parsers throw nothing but http::ApiError 400/422; a request they accept has APs
// of type wifi/ble with an rss in [-120, 0]; an accepted transmitter has a normalised bssid
// and its type; a fix is finite, uses at least 3 transmitters, and its ellipse is not negative;
// the nearest transmitter is one heard, the strongest, at a finite range not below 0.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "http/api_error.hpp"
#include "http/localize/ranging_localize.hpp"
#include "http/transmitters/transmitter_fields.hpp"
#include "json_mutator.hpp"
#include "locus/radio_map.hpp"
#include "transmitters/ranging_scan.hpp"

using namespace locus;
using namespace locus::http;

namespace {

[[noreturn]] void fail(const char* what, const std::string& body) {
    std::fprintf(stderr, "fuzz_ranging: %s\nbody (%zu bytes): %s\n", what, body.size(), body.c_str());
    std::abort();
}

void check(bool ok, const char* what, const std::string& body) {
    if (!ok) fail(what, body);
}

void check_refusal(const ApiError& e, const std::string& body) {
    check(e.status == 400 || e.status == 422, "an ApiError with a status other than 400/422", body);
    check(!e.code.empty() && *e.what() != '\0', "an ApiError without a code or message", body);
}

void check_fix(const std::optional<ranging::Fix>& fix, std::size_t heard, const std::string& body) {
    if (!fix) return;
    check(std::isfinite(fix->at.x) && std::isfinite(fix->at.y), "a fix that is not finite", body);
    check(fix->used >= 3 && static_cast<std::size_t>(fix->used) <= heard, "a fix from fewer than 3 or more than heard", body);
    check(!(fix->uncertainty.semi_major < 0) && !(fix->uncertainty.semi_minor < 0), "a negative ellipse axis", body);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string body(reinterpret_cast<const char*>(data), size);
    try {
        if (const auto r = parse_ranging_request(body)) {
            std::vector<ranging::Heard> heard;
            transmitters::KnownTransmitters known;
            for (const auto& ap : r->query.aps) {
                check(ap.type == "wifi" || ap.type == "ble", "an AP type other than wifi/ble", body);
                check(valid_rss(ap.rss), "an rss outside [-120, 0]", body);
                const std::size_t h = std::hash<std::string>{}(ap.bssid);
                ranging::Transmitter t{{static_cast<double>(h % 4000) / 100.0, static_cast<double>((h / 4000) % 2500) / 100.0},
                                       static_cast<double>((h / 10'000'000) % 300) / 100.0,
                                       {-30.0 - static_cast<double>(h % 50), 1.5 + static_cast<double>(h % 30) / 10.0}};
                heard.push_back({t, ap.rss});
                known.by_key[transmitters::transmitter_key(ap.type, ap.bssid)] = {1, t, static_cast<std::int64_t>(h % 1000), ""};
            }
            if (!heard.empty()) {
                const auto n = transmitters::nearest_transmitter(known, r->query);
                check(n.transmitter && n.heard == heard.size(), "no nearest transmitter, or a wrong count, for a scan of known ones", body);
                for (const auto& ap : r->query.aps) check(!(ap.rss > n.rss), "a nearest transmitter weaker than another heard", body);
                check(std::isfinite(n.range_m) && n.range_m >= 0.0, "a range that is not finite or below 0", body);
            }
            if (heard.size() >= 3) {
                check_fix(ranging::trilaterate(heard, r->trilateration), heard.size(), body);
                check_fix(ranging::multilaterate(heard, r->multilateration_options), heard.size(), body);
            }
        }
    } catch (const ApiError& e) {
        check_refusal(e, body);
    }
    const nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
    if (j.is_object())
        for (const bool create : {true, false}) {
            try {
                const auto f = transmitter_fields(j, create);
                if (f.has("bssid")) {
                    const auto& b = f.get<std::string>("bssid");
                    check(Bssid(b).str() == b, "a bssid not in its normal form", body);
                }
                if (create) check(f.has("type") && f.has("x") && f.has("y") && f.has("tx_power"), "a create without its required fields", body);
            } catch (const ApiError& e) {
                check_refusal(e, body);
            }
        }
    return 0;
}

LOCUS_FUZZ_JSON_MUTATOR
