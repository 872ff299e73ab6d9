#include <gtest/gtest.h>

#include "http/api_error.hpp"
#include "http/validation.hpp"
#include "store/kinds.hpp"

namespace validation_test {
namespace {

using locus::http::ApiError;
using nlohmann::json;
namespace http = locus::http;

std::string code_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const ApiError& e) {
        return std::to_string(e.status) + " " + e.code;
    }
    return "ok";
}
const locus::store::Kind& floors() { return locus::store::kind("floors"); }

TEST(Validation, ParseObjectRefusesAnythingButAnObject) {
    EXPECT_EQ(code_of([] { http::parse_object("{\"a\":1}"); }), "ok");
    EXPECT_EQ(code_of([] { http::parse_object("[]"); }), "400 invalid_json");
    EXPECT_EQ(code_of([] { http::parse_object("{"); }), "400 invalid_json");
    EXPECT_EQ(code_of([] { http::parse_object("1e999"); }), "400 invalid_json");
}

TEST(Validation, NestingPastTheLimitIsRefusedAndBracketsInStringsAreText) {
    const auto nested = [](std::size_t depth) { return "{\"a\":" + std::string(depth - 1, '[') + std::string(depth - 1, ']') + "}"; };
    EXPECT_EQ(code_of([&] { http::parse_object(nested(http::kMaxJsonDepth)); }), "ok");
    EXPECT_EQ(code_of([&] { http::parse_object(nested(http::kMaxJsonDepth + 1)); }), "400 invalid_json");
    // Unclosed, as an attack sends it: refused before any tree is built.
    EXPECT_EQ(code_of([] { http::parse_object("{\"a\":" + std::string(1'000'000, '[')); }), "400 invalid_json");
    const std::string in_text = "{\"a\":\"" + std::string(200, '[') + "\\\"" + std::string(200, '{') + "\"}";
    EXPECT_EQ(code_of([&] { http::parse_object(in_text); }), "ok");
}

TEST(Validation, CreateNeedsRequiredFieldsPatchDoesNot) {
    const json full = {{"name", "F"}, {"level", 2}, {"width", 10.5}, {"height", 3}};
    const auto v = http::validated_fields(floors(), full, true);
    EXPECT_EQ(v.get<std::int64_t>("level"), 2);
    EXPECT_DOUBLE_EQ(v.get<double>("height"), 3.0);
    EXPECT_FALSE(v.has("north_offset_deg"));
    EXPECT_EQ(code_of([] { http::validated_fields(floors(), {{"name", "F"}}, true); }), "422 invalid_field");
    EXPECT_EQ(code_of([] { http::validated_fields(floors(), {{"name", "F"}}, false); }), "ok");
}

TEST(Validation, IntegersMayBeWrittenAsIntegralFloats) {
    const auto v = http::validated_fields(floors(), {{"level", 2.0}}, false);
    EXPECT_TRUE(std::holds_alternative<std::int64_t>(v.values.at("level")));
    EXPECT_EQ(code_of([] { http::validated_fields(floors(), {{"level", 2.5}}, false); }), "422 invalid_field");
}

TEST(Validation, ReadOnlyAndIdFieldsAreIgnoredUnknownOnesRefused) {
    const auto& rps = locus::store::kind("rps");
    const auto v = http::validated_fields(rps, {{"id", 3}, {"radiomap_id", 9}, {"scans", 100}, {"name", "a"}}, false);
    EXPECT_EQ(v.values.size(), 1u);
    EXPECT_EQ(v.get<std::string>("name"), "a");
    EXPECT_EQ(code_of([&] { http::validated_fields(rps, {{"nmae", "a"}}, false); }), "422 invalid_field");
}

TEST(Validation, ReadingsAreNormalisedAndRangeChecked) {
    const auto r = http::parse_reading({{"bssid", " AA-BB-CC-DD-EE-FF "}, {"rss", -61}}, "r");
    EXPECT_EQ(r.bssid.str(), "aa:bb:cc:dd:ee:ff");
    EXPECT_EQ(r.type, "wifi");
    EXPECT_DOUBLE_EQ(r.rss, -61.0);
    EXPECT_EQ(code_of([] { http::parse_reading({{"bssid", "a"}, {"rss", 100}}, "r"); }), "422 out_of_range");
    EXPECT_EQ(code_of([] { http::parse_reading({{"bssid", "a"}, {"rss", -120.01}}, "r"); }), "422 out_of_range");
    EXPECT_EQ(code_of([] { http::parse_reading({{"bssid", "   "}, {"rss", -50}}, "r"); }), "422 invalid_field");
    EXPECT_EQ(code_of([] { http::parse_reading({{"bssid", "a"}, {"rss", nullptr}}, "r"); }), "422 invalid_field");
}

TEST(Validation, MeasurementsNeedSaneStatistics) {
    const auto m = http::parse_measurement({{"bssid", "x"}, {"mean", -50}, {"variance", 0}, {"count", 1}}, "m");
    EXPECT_EQ(m.stats.count, 1);
    EXPECT_EQ(code_of([] { http::parse_measurement({{"bssid", "x"}, {"mean", -50}, {"variance", -1}, {"count", 1}}, "m"); }),
              "422 out_of_range");
    EXPECT_EQ(code_of([] { http::parse_measurement({{"bssid", "x"}, {"mean", -50}, {"variance", 1}, {"count", 0}}, "m"); }),
              "422 out_of_range");
    EXPECT_EQ(code_of([] { http::parse_measurement({{"bssid", "x"}, {"mean", -50}, {"variance", 1}, {"count", 1.5}}, "m"); }),
              "422 invalid_field");
}

TEST(Validation, IdsAndPages) {
    EXPECT_EQ(http::parse_id("42", "map"), 42);
    EXPECT_EQ(code_of([] { http::parse_id("0", "map"); }), "404 not_found");
    EXPECT_EQ(code_of([] { http::parse_id("99999999999999999999", "map"); }), "404 not_found");
    EXPECT_EQ(http::parse_page(std::string("5"), std::string("10")).offset, 10);
    EXPECT_EQ(http::parse_page(std::nullopt, std::nullopt).limit, 100);
    EXPECT_EQ(code_of([] { http::parse_page(std::string("1001"), std::nullopt); }), "400 invalid_query");
}

TEST(Validation, ErrorMessagesNameThePlaceInTheBody) {
    try {
        http::parse_scans(json::array({json::array({{{"bssid", "a"}, {"rss", -50}}, {{"bssid", "b"}, {"rss", 5}}})}), "scans");
        FAIL() << "an out-of-range reading must be refused";
    } catch (const ApiError& e) {
        EXPECT_NE(std::string(e.what()).find("scans[0][1].rss"), std::string::npos) << e.what();
    }
}

// The white space trimmed around a BSSID is the C locale's set, no more and no less.
TEST(Validation, BssidWhiteSpaceIsTheSixAsciiSpaces) {
    EXPECT_STREQ(http::bssid_problem(std::string_view("\t\n\v\f\r ")), "must not be blank");
    EXPECT_STREQ(http::bssid_problem(std::string_view(" \x01 ")), "holds control characters");  // not white space
    EXPECT_EQ(http::bssid_problem(std::string_view("\v a \f")), nullptr);
    EXPECT_EQ(locus::Bssid("\v AA-BB-CC-DD-EE-FF\r\n").str(), "aa:bb:cc:dd:ee:ff");
    EXPECT_EQ(locus::Bssid("\x1c" "ab").str(), "\x1c" "ab");  // a separator, not white space
}

}  // namespace
}  // namespace validation_test
