// The localize fast path (server/http/localize/plain_localize_request.hpp): for every body it accepts, the
// result must be exactly what the full parser gives; everything unusual must be declined.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "datasets/uji_csv.hpp"
#include "http/api_error.hpp"
#include "http/localize/plain_localize_request.hpp"
#include "http/validation.hpp"
#include "build_paths.hpp"

namespace plain_request_test {
namespace {

using namespace locus;
using namespace locus::http;

std::optional<LocalizeRequest> full(const std::string& body) {
    try {
        return parse_localize_request_in_full(body);
    } catch (const http::ApiError&) {
        return std::nullopt;
    }
}

// Same algorithm, same query (bit for bit), same options.
void expect_same(const LocalizeRequest& a, const LocalizeRequest& b, const std::string& body) {
    EXPECT_EQ(a.algorithm, b.algorithm) << body;
    ASSERT_EQ(a.query.aps.size(), b.query.aps.size()) << body;
    for (std::size_t i = 0; i < a.query.aps.size(); ++i) {
        EXPECT_EQ(a.query.aps[i].type, b.query.aps[i].type) << body;
        EXPECT_EQ(a.query.aps[i].bssid, b.query.aps[i].bssid) << body;
        EXPECT_EQ(std::signbit(a.query.aps[i].rss), std::signbit(b.query.aps[i].rss)) << body;
        EXPECT_EQ(a.query.aps[i].rss, b.query.aps[i].rss) << body;
    }
    EXPECT_EQ(a.options.k, b.options.k);
    EXPECT_EQ(a.options.candidates, b.options.candidates);
    EXPECT_FALSE(a.options.near.has_value());
    EXPECT_FALSE(b.options.near.has_value());
}

// Accepted by the fast path, and identical to the full parse.
void expect_fast(const std::string& body) {
    const auto fast = parse_plain_localize_request(body);
    ASSERT_TRUE(fast.has_value()) << "declined: " << body;
    const auto reference = full(body);
    ASSERT_TRUE(reference.has_value()) << "the full parser refuses: " << body;
    expect_same(*fast, *reference, body);
}

const std::vector<std::string> kPlain = {
    R"({"algorithm":"nn","scans":[[{"bssid":"aa:bb:cc:dd:ee:ff","rss":-61}]]})",
    R"({"scans":[[{"rss":-61.5,"bssid":"AA-BB-CC-DD-EE-01","type":"wifi"},{"type":"ble","bssid":"beacon 7","rss":-80}]]})",
    " \n{ \"scans\" : [ [ { \"bssid\" : \" x1 \" , \"rss\" : -7e1 } ] , [ {\"bssid\":\"x1\",\"rss\":-72.25E0} ] ] ,\r\n\t\"algorithm\" : \"bayes\" } \n",
    R"({"scans":[[{"bssid":"a","rss":0},{"bssid":"b","rss":-0},{"bssid":"c","rss":-120},{"bssid":"a","rss":-10.0}]]})",
    R"({"scans":[[{"type":"ble","bssid":")" + std::string(63, 'q') + R"(","rss":-99}]],"algorithm":"knn"})",
};

TEST(PlainRequest, TakesThePlainShapesAndAgreesWithTheFullParser) {
    for (const auto& body : kPlain) expect_fast(body);
    const auto r = parse_plain_localize_request(kPlain[2]);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->algorithm, match::Algorithm::bayes);
    ASSERT_EQ(r->query.aps.size(), 1u);  // one AP in two scans: averaged, trimmed
    EXPECT_EQ(r->query.aps[0].bssid, "x1");
    EXPECT_DOUBLE_EQ(r->query.aps[0].rss, -71.125);
}

TEST(PlainRequest, EdgesOfWhatItTakesAgreeWithTheFullParser) {
    expect_fast(R"({"scans":[[{"bssid":")" + std::string(64, 'b') + R"(","rss":-60}]]})");  // the longest bssid
    EXPECT_FALSE(parse_plain_localize_request(R"({"scans":[[{"bssid":")" + std::string(65, 'b') + R"(","rss":-60}]]})"));
    expect_fast(R"({"scans":[[{"bssid":"a","rss":-61.123456789012345678},{"bssid":"b","rss":-1e-300},{"bssid":"c","rss":-6.1E+1}]]})");
    expect_fast(R"({"scans":[[{"bssid":"a","rss":-120}]],"algorithm":"bsbnn"})");
    expect_fast("{\"scans\":[[{\"bssid\":\"a\x7f\",\"rss\":-60}]]}");  // DEL needs no escape in JSON
    EXPECT_FALSE(parse_plain_localize_request(R"({"scans":[[{"bssid":"a","rss":-1e400}]]})"));
}

TEST(PlainRequest, DeclinesWhatItDoesNotReadWithCertainty) {
    for (const char* body : {
             R"({"scans":[[{"bssid":"a\u0041","rss":-60}]]})",             // escape
             R"({"scans":[[{"bssid":"é","rss":-60}]]})",                   // non-ASCII
             R"({"scans":[[{"bssid":"a","rss":-60}]],"options":{"k":1}})",  // options
             R"({"measurements":[{"bssid":"a","rss":-60}]})",              // means
             R"({"scans":[[{"bssid":"a","rss":-60,"type":null}]]})",       // null
             R"({"scans":[[{"bssid":"a","bssid":"b","rss":-60}]]})",       // duplicate key
             R"({"scans":[[{"bssid":"a","rss":-60}]],"scans":[[{"bssid":"a","rss":-60}]]})",
             R"({"scans":[[{"bssid":"a","rss":-60}]]} x)",                 // trailing text
             R"({"scans":[]})", R"({"scans":[[]]})", R"({})", R"([])", "",
             R"({"scans":[[{"bssid":"a","rss":-60}]],"algorithm":"magic"})",
             R"({"scans":[[{"bssid":"a","rss":-60,"extra":1}]]})",
             R"({"scans":[[{"bssid":"a","rss":10}]]})",                    // out of range
             R"({"scans":[[{"bssid":"a","rss":-60.}]]})", R"({"scans":[[{"bssid":"a","rss":-060}]]})",
             R"({"scans":[[{"bssid":"a","rss":+60}]]})", R"({"scans":[[{"bssid":"a","rss":-1234567890123456}]]})",
             R"({"scans":[[{"bssid":"  ","rss":-60}]]})", R"({"scans":[[{"bssid":"a","rss":-60,"type":"lte"}]]})",
             R"({"scans":[[{"bssid":"a","rss":-60},]]})",
             R"({"algorithm":"nn","algorithm":"bayes","scans":[[{"bssid":"a","rss":-60}]]})",  // the full parser keeps the last
             R"({"scans":[[{"bssid":"a","rss":-60,"rss":-70}]]})",
             R"({"scans":[[{"bssid":"a","type":"ble","type":"wifi","rss":-60}]]})",
             R"({"scans":[[{"bssid":"a","rss":-12345678901234567}]]})",  // too long for the integer reader, in any case
             "\xef\xbb\xbf{\"scans\":[[{\"bssid\":\"a\",\"rss\":-60}]]}",  // byte-order mark
         })
        EXPECT_FALSE(parse_plain_localize_request(body).has_value()) << body;
}

// Thousands of mutated bodies: whatever the fast path accepts, the full parser reads the same.
TEST(PlainRequest, MutatedBodiesNeverDisagreeWithTheFullParser) {
    std::mt19937 rng(20261122);
    const std::string alphabet = std::string("{}[]:,\" -.0123456789eE+abtrsnulypwifl\\\t\r\n\x7f\xc3") + '\0';
    std::size_t accepted = 0, total = 0;
    for (const auto& base : kPlain) {
        for (int n = 0; n < 3000; ++n) {
            std::string body = base;
            const int edits = 1 + static_cast<int>(rng() % 3);
            for (int e = 0; e < edits && !body.empty(); ++e) {
                const std::size_t at = rng() % body.size();
                const char c = alphabet[rng() % alphabet.size()];
                switch (rng() % 4) {
                    case 0: body[at] = c; break;
                    case 1: body.erase(at, 1); break;
                    case 2: body.insert(body.begin() + static_cast<std::ptrdiff_t>(at), c); break;
                    default: body.resize(at); break;
                }
            }
            ++total;
            const auto fast = parse_plain_localize_request(body);
            if (!fast) continue;
            ++accepted;
            const auto reference = full(body);
            ASSERT_TRUE(reference.has_value()) << "the fast path took a body the full parser refuses: " << body;
            expect_same(*fast, *reference, body);
        }
    }
    // Many mutations only change a digit or a name: the comparison must have had work to do.
    EXPECT_GT(accepted, total / 20) << accepted << " of " << total;
}

TEST(PlainRequest, RealScansTakeTheFastPath) {
    const std::string path = std::string(LOCUS_DATA_DIR) + "/ujiindoorloc/trainingData.csv";
    if (!std::ifstream(path)) GTEST_SKIP() << "UJIIndoorLoc not found under LOCUS_DATA_DIR/ujiindoorloc";
    namespace uji = locus::datasets::uji;
    const uji::Data data = uji::read_file(path);
    std::size_t checked = 0;
    for (std::size_t i = 0; i < data.rows.size(); i += 97) {
        if (data.rows[i].heard.empty()) continue;
        nlohmann::json readings = nlohmann::json::array();
        for (const auto& r : uji::scan_of(data, data.rows[i])) readings.push_back({{"bssid", r.bssid}, {"rss", r.rss}});
        expect_fast(nlohmann::json{{"algorithm", "wknn"}, {"scans", {readings}}}.dump());
        ++checked;
    }
    EXPECT_GT(checked, 150u);
}

}  // namespace
}  // namespace plain_request_test

namespace plain_request_limits_test {
namespace {

using namespace locus::http;

std::string reading_text(int i) {
    char bssid[18];
    std::snprintf(bssid, sizeof bssid, "aa:bb:cc:%02x:%02x:%02x", (i >> 16) & 0xff, (i >> 8) & 0xff, i & 0xff);
    return std::string(R"({"bssid":")") + bssid + R"(","rss":-60})";
}

// `scans` scans of `per_scan` readings each.
std::string scans_body(std::size_t scans, std::size_t per_scan) {
    std::string body = R"({"scans":[)";
    for (std::size_t s = 0; s < scans; ++s) {
        body += s ? ",[" : "[";
        for (std::size_t r = 0; r < per_scan; ++r) body += (r ? "," : "") + reading_text(static_cast<int>(r));
        body += "]";
    }
    return body + "]}";
}

std::string refusal(const std::string& body) {
    try {
        (void)parse_localize_request_in_full(body);
        return "ok";
    } catch (const ApiError& e) {
        return std::to_string(e.status) + " " + e.code + ": " + e.what();
    }
}

TEST(LocalizeRequestLimits, ScansAndReadingsAreCountedWhileParsing) {
    EXPECT_EQ(refusal(scans_body(kMaxScans, 1)), "ok");
    EXPECT_TRUE(parse_plain_localize_request(scans_body(kMaxScans, 1)).has_value());
    EXPECT_EQ(refusal(scans_body(kMaxScans + 1, 1)), "422 out_of_range: 'scans' holds more than 1000 scans");
    EXPECT_FALSE(parse_plain_localize_request(scans_body(kMaxScans + 1, 1)).has_value());  // the full parser words it
    EXPECT_EQ(refusal(scans_body(1, kMaxReadings)), "ok");
    EXPECT_EQ(refusal(scans_body(2, kMaxReadings + 1)), "422 out_of_range: 'scans[0]' holds more than 10000 readings");
    EXPECT_FALSE(parse_plain_localize_request(scans_body(1, kMaxReadings + 1)).has_value());
    std::string means = R"({"measurements":[)";
    for (std::size_t r = 0; r <= kMaxReadings; ++r) means += (r ? "," : "") + reading_text(static_cast<int>(r));
    EXPECT_EQ(refusal(means + "]}"), "422 out_of_range: 'measurements' holds more than 10000 readings");
}

TEST(LocalizeRequestLimits, MillionsOfEmptyScansStopAtTheLimit) {
    // 8 MiB of `[],`: once read into millions of empty scans (some 110 MiB), now refused at the 1,001st.
    std::string body = R"({"scans":[)";
    for (int i = 0; i < 2'000'000; ++i) body += i ? ",[]" : "[]";
    body += "]}";
    EXPECT_EQ(refusal(body), "422 out_of_range: 'scans' holds more than 1000 scans");
}

TEST(LocalizeRequestLimits, NestingDeeperThanTheLimitIsRefusedBeforeParsing) {
    const auto nested = [](std::size_t depth) {
        return R"({"scans":[[)" + reading_text(1) + R"(]],"options":{"near":)" + std::string(depth, '[') + std::string(depth, ']') + "}}";
    };
    EXPECT_NE(refusal(nested(kMaxJsonDepth - 3)).find("400 invalid_json"), 0u);  // deep, within the limit: another answer
    EXPECT_EQ(refusal(nested(kMaxJsonDepth)), "400 invalid_json: the request body nests arrays and objects deeper than 64 levels");
}

}  // namespace
}  // namespace plain_request_limits_test
