// Inputs the fuzz targets (fuzz/) found to crash or misbehave, one test each. Their full
// crashing inputs are in fuzz/corpus/; these are the smallest forms. Run under
// scripts/test_sanitized.sh they would report the original memory errors.
#include <gtest/gtest.h>

#include <string>

#include "http/api_error.hpp"
#include "localize/request.hpp"

using namespace locus;

namespace {

int status_of(const std::string& body) {
    try {
        localize::parse_localize_request(body);
        return 200;
    } catch (const http::ApiError& e) {
        return e.status;
    }
}

}  // namespace

// An object nested in a misplaced object under "scans" opened a reading with no scan to hold
// it: scans.back() on an empty list (fuzz/corpus/fuzz_localize_request/crash_reading_outside_scan).
TEST(FuzzRegressions, AReadingOutsideAScanIsRefusedWithoutTouchingMemory) {
    EXPECT_EQ(status_of(R"({"scans":[{"x":{"bssid":"a","rss":-1}}]})"), 422);
    EXPECT_EQ(status_of(R"({"scans":[{"x":{"bssid":"a","rss":-1,"type":"wifi"}},[{"bssid":"b","rss":-2}]]})"), 422);
    EXPECT_EQ(status_of(R"({"scans":{"s":[{"bssid":"a","rss":-1}]}})"), 422);
    EXPECT_EQ(status_of(R"({"scans":[[{"bssid":"a","rss":-1}]]})"), 200);
}
