// Inputs the fuzz targets (fuzz/) found to crash or misbehave, one test each. Their full
// crashing inputs are in fuzz/corpus/; these are the smallest forms. Run under
// scripts/test_sanitized.sh they would report the original memory errors.
#include <gtest/gtest.h>

#include <string>

#include "http/api_error.hpp"
#include "http/validation.hpp"
#include "http/localize/localize_request.hpp"
#include "http/tracks/track_request.hpp"
#include "http/crud/store_json.hpp"
#include "store/sql_store.hpp"

namespace fuzz_regressions_test {
namespace {

using namespace locus;

int status_of(const std::string& body) {
    try {
        http::parse_localize_request(body);
        return 200;
    } catch (const http::ApiError& e) {
        return e.status;
    }
}

// An object nested in a misplaced object under "scans" opened a reading with no scan to hold
// it: scans.back() on an empty list (fuzz/corpus/fuzz_localize_request/crash_reading_outside_scan).
TEST(FuzzRegressions, AReadingOutsideAScanIsRefusedWithoutTouchingMemory) {
    EXPECT_EQ(status_of(R"({"scans":[{"x":{"bssid":"a","rss":-1}}]})"), 422);
    EXPECT_EQ(status_of(R"({"scans":[{"x":{"bssid":"a","rss":-1,"type":"wifi"}},[{"bssid":"b","rss":-2}]]})"), 422);
    EXPECT_EQ(status_of(R"({"scans":{"s":[{"bssid":"a","rss":-1}]}})"), 422);
    EXPECT_EQ(status_of(R"({"scans":[[{"bssid":"a","rss":-1}]]})"), 200);
}

// A measurement with "type": null passed validation (null is "absent", so wifi) but the
// store's import read it with json::value(), which throws on a null: the server answered 422
// with nlohmann's "type must be string, but is null" instead of importing it
// (fuzz/corpus/fuzz_radiomap_import/crash_null_type.json).
TEST(FuzzRegressions, AnImportedMeasurementWithANullTypeIsWifi) {
    using locus::store::kind;
    locus::store::SqlStore repo(":memory:");
    const auto map = repo.create(kind("maps"), std::nullopt, {{"name", "m"}}).id;
    const auto building = repo.create(kind("buildings"), map, {{"name", "b"}}).id;
    const auto floor = repo.create(kind("floors"), building, {{"name", "f"}, {"level", 0}, {"width", 10.0}, {"height", 10.0}})
                           .id;
    const auto doc = nlohmann::json::parse(
        R"({"name":"n","rps":[{"name":"r","x":0,"y":0,"measurements":[{"type":null,"bssid":"a","mean":-50,"variance":1,"count":1}]}]})");
    const auto row = repo.import_radiomap(floor, http::parse_radiomap_document(doc));
    const auto exported = http::export_json(repo.export_radiomap(row.radiomap.id));
    EXPECT_EQ(exported.at("rps").at(0).at("measurements").at(0).at("type"), "wifi");
}

// A heading just below zero, -1e-300, was shifted into [0, 360) by adding 360, which rounds
// to exactly 360: the step went in with a heading the docs say cannot be
// (fuzz/corpus/fuzz_track_request/crash_heading_rounds_to_360.json).
TEST(FuzzRegressions, AHeadingJustBelowNorthIsNorth) {
    const auto in = http::parse_steps_request(
        nlohmann::json::parse(R"({"steps":[{"t":1700000001,"length_m":0.7,"heading_deg":-1e-300},)"
                              R"({"t":1700000002,"length_m":0.7,"heading_deg":-90}]})"),
        1e12);
    ASSERT_EQ(in.steps.size(), 2u);
    EXPECT_EQ(in.steps[0].heading_deg, 0.0);
    EXPECT_EQ(in.steps[1].heading_deg, 270.0);
}

}  // namespace
}  // namespace fuzz_regressions_test
