// The scan upload body (POST /v1/rps/{id}/scans): parse_object, then parse_scans +
// aggregate_scans for raw scans or parse_measurements (+ merging an AP sent twice) for
// aggregates, as the handler in server/http/radiomaps/radiomap_routes.cpp does (kept in step with it by hand).
//
// Checks: nothing but http::ApiError (400/422) escapes; an accepted upload holds each
// (type, bssid) once, normalised, with counts in [1, 2^53] and a scan count of at most 2^53; and
// each aggregate it would store reads back through parse_measurement (what a radio-map
// import accepts), so an upload can never store what an export/import round trip refuses.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "http/api_error.hpp"
#include "http/validation.hpp"
#include "http/crud/store_json.hpp"
#include "store/documents.hpp"
#include "json_mutator.hpp"

using namespace locus;
using nlohmann::json;

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail, const std::string& body) {
    std::fprintf(stderr, "fuzz_scan_upload: %s %s\nbody (%zu bytes): %s\n", what, detail.c_str(), body.size(),
                 body.c_str());
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string body(reinterpret_cast<const char*>(data), size);
    store::ScanBatch upload;
    try {
        upload = http::parse_scan_upload(body);
    } catch (const http::ApiError& e) {
        if (e.status != 400 && e.status != 422) fail("an ApiError with status", std::to_string(e.status), body);
        return 0;
    }
    // An empty "measurements" array is a no-op upload (its upload_id is still recorded).
    if (upload.scans < (upload.measurements.empty() ? 0 : 1) || upload.scans > kMaxCount)
        fail("a scan count of", std::to_string(upload.scans), body);
    if (upload.upload_id && (upload.upload_id->empty() || upload.upload_id->size() > 200)) fail("an upload_id", "", body);
    std::set<std::pair<std::string, std::string>> seen;
    for (const auto& m : upload.measurements) {
        if (!seen.emplace(m.type, m.bssid).second) fail("an AP twice:", m.bssid, body);
        if (Bssid(m.bssid.str()) != m.bssid) fail("a bssid not normalised:", m.bssid, body);
        if (m.stats.count < 1 || m.stats.count > kMaxCount) fail("a count of", std::to_string(m.stats.count), body);
        // What the store would keep for a fresh RP, as an export writes it and an import reads it.
        const json exported = http::measurement_json(m);
        try {
            http::parse_measurement(exported, "m");
        } catch (const http::ApiError& e) {
            fail("an aggregate an import would refuse:", exported.dump(-1, ' ', false, json::error_handler_t::replace) + " (" + e.what() + ")", body);
        }
    }
    return 0;
}

LOCUS_FUZZ_JSON_MUTATOR
