// Every kind of bad input gets a 4xx with {"error":{"code","message"}}, writes nothing, and
// leaves the server serving.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

#include "bench_connection.hpp"
#include "hierarchy.hpp"
#include "server_process.hpp"

namespace server_bad_input_test {
namespace {

using locus::testing::Response;
using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

void expect_error(const Response& r, int status, const std::string& code, const std::string& context) {
    EXPECT_EQ(r.status, status) << context << ": " << r.raw;
    ASSERT_TRUE(r.body.is_object()) << context << ": body is not JSON: " << r.raw;
    ASSERT_TRUE(r.body.contains("error")) << context << ": " << r.raw;
    EXPECT_EQ(r.body["error"]["code"], code) << context << ": " << r.raw;
    EXPECT_TRUE(r.body["error"]["message"].is_string()) << context;
    EXPECT_FALSE(r.body["error"]["message"].get<std::string>().empty()) << context;
}

struct BadInput : ::testing::Test {
    ServerProcess s;
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    std::int64_t rp = locus::testing::make_rp(s, h.radiomap, "rp-1", 2.0, 3.0);
    std::string scans = "/v1/rps/" + std::to_string(rp) + "/scans";
    std::string floors = "/v1/buildings/" + std::to_string(h.building) + "/floors";

    json rp_state() { return body_of(s.get("/v1/rps/" + std::to_string(rp))); }
    void TearDown() override { EXPECT_EQ(s.get("/health").status, 200) << "the server must keep serving"; }
};

// Built by appending: GCC 12 misfires -Wrestrict on `literal + std::string(n, c) + literal`.
std::string name_body(std::size_t length) {
    std::string body = R"({"name":")";
    body.append(length, 'x');
    body.append(R"("})");
    return body;
}

json one_scan(const json& rss) { return json::array({json::array({{{"bssid", "aa:bb:cc:dd:ee:ff"}, {"rss", rss}}})}); }

TEST_F(BadInput, MalformedJson) {
    for (const std::string body : {"{", "{\"name\": }", "not json", "", "{\"name\":\"a\"} trailing"})
        expect_error(s.post_raw("/v1/maps", body), 400, "invalid_json", "body '" + body + "'");
    expect_error(s.post_raw("/v1/maps", "[1,2]"), 400, "invalid_json", "array body");
    expect_error(s.post_raw(scans, "{\"scans\": [[{\"bssid\":\"a\",\"rss\":-50}]"), 400, "invalid_json", "truncated scans");
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 1);
}

TEST_F(BadInput, ANulByteEndsNothing) {
    // nlohmann's lexer reads NUL as the end of input; a body with junk after one is refused.
    using namespace std::string_literals;
    expect_error(s.post_raw("/v1/maps", "{\"name\":\"x\"}\0junk"s), 400, "invalid_json", "map after NUL");
    expect_error(s.post_raw(scans, "{\"scans\": [[{\"bssid\":\"a\",\"rss\":-50}]]}\0"s), 400, "invalid_json", "scans then NUL");
    const std::string localize = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize";
    expect_error(s.post_raw(localize, "{\"algorithm\":\"wknn\",\"scans\":[[{\"bssid\":\"a\",\"rss\":-50}]]}\0junk"s), 400,
                 "invalid_json", "localize after NUL");
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 1);
    EXPECT_TRUE(rp_state().at("measurements").empty());
}

TEST_F(BadInput, NanAndInfinityAreRefused) {
    // JSON has no NaN or Infinity; the literals and overflowing numbers are malformed JSON.
    for (const std::string v : {"NaN", "nan", "Infinity", "-Infinity", "1e999", "-1e999"}) {
        expect_error(s.post_raw(scans, "{\"scans\": [[{\"bssid\":\"aa\",\"rss\":" + v + "}]]}"), 400, "invalid_json", v);
        expect_error(s.post_raw(floors, R"({"name":"F","level":1,"width":)" + v + R"(,"height":3})"), 400, "invalid_json", v);
    }
    EXPECT_TRUE(rp_state().at("measurements").empty());
}

TEST_F(BadInput, WrongTypes) {
    expect_error(s.post("/v1/maps", {{"name", 42}}), 422, "invalid_field", "numeric name");
    expect_error(s.post(floors, {{"name", "F"}, {"level", "one"}, {"width", 3}, {"height", 3}}), 422, "invalid_field", "string level");
    expect_error(s.post(floors, {{"name", "F"}, {"level", 1.5}, {"width", 3}, {"height", 3}}), 422, "invalid_field", "fractional level");
    expect_error(s.post(floors, {{"name", "F"}, {"level", 1}, {"width", "3"}, {"height", 3}}), 422, "invalid_field", "string width");
    expect_error(s.post(floors, {{"name", "F"}, {"level", true}, {"width", 3}, {"height", 3}}), 422, "invalid_field", "bool level");
    expect_error(s.post("/v1/floors/" + std::to_string(h.floor) + "/rooms", {{"name", "R"}, {"rects", "big"}}), 422, "invalid_field", "rects string");
    expect_error(s.post(scans, {{"scans", "lots"}}), 422, "invalid_field", "scans string");
    expect_error(s.post(scans, {{"scans", json::array({json::object()})}}), 422, "invalid_field", "scan object");
    expect_error(s.post(scans, {{"scans", one_scan("-50")}}), 422, "invalid_field", "rss string");
    expect_error(s.post(scans, {{"upload_id", 7}, {"scans", one_scan(-50)}}), 422, "invalid_field", "upload id number");
    expect_error(s.post(scans, {{"measurements", {{{"bssid", "aa"}, {"mean", -50}, {"variance", 1}, {"count", "3"}}}}}), 422, "invalid_field", "count string");
    EXPECT_TRUE(rp_state().at("measurements").empty());
}

TEST_F(BadInput, MissingAndUnknownFields) {
    expect_error(s.post("/v1/maps", json::object()), 422, "invalid_field", "no name");
    expect_error(s.post("/v1/maps", {{"name", ""}}), 422, "invalid_field", "empty name");
    expect_error(s.post(floors, {{"name", "F"}, {"level", 1}, {"height", 3}}), 422, "invalid_field", "no width");
    expect_error(s.post("/v1/radiomaps/" + std::to_string(h.radiomap) + "/rps", {{"name", "x"}, {"y", 1}}), 422, "invalid_field", "no x");
    expect_error(s.post("/v1/maps", {{"name", "M2"}, {"colour", "red"}}), 422, "invalid_field", "unknown field");
    expect_error(s.post(scans, json::object()), 422, "invalid_field", "neither scans nor measurements");
    expect_error(s.post(scans, {{"scans", one_scan(-50)}, {"measurements", json::array()}}), 422, "invalid_field", "both");
    expect_error(s.post(scans, {{"scans", json::array({json::array({{{"rss", -50}}})})}}), 422, "invalid_field", "no bssid");
    expect_error(s.post(scans, {{"scans", json::array({json::array({{{"bssid", "aa"}}})})}}), 422, "invalid_field", "no rss");
    expect_error(s.post(scans, {{"scans", json::array({json::array({{{"bssid", "aa"}, {"rss", -50}, {"type", "lte"}}})})}}), 422,
                 "invalid_field", "unknown type");
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 1);
}

TEST_F(BadInput, RssOutsideTheValidRange) {
    for (double v : {100.0, 0.5, -120.5, -1000.0})
        expect_error(s.post(scans, {{"scans", one_scan(v)}}), 422, "out_of_range", "rss " + std::to_string(v));
    expect_error(s.post(scans, {{"measurements", {{{"bssid", "aa"}, {"mean", 3.0}, {"variance", 1}, {"count", 3}}}}}), 422,
                 "out_of_range", "mean above 0");
    // The numbers are written as the client would write them, not as "100.000000".
    const auto r = s.post(scans, {{"scans", one_scan(100)}});
    EXPECT_NE(r.raw.find("= 100 is outside [-120, 0]"), std::string::npos) << r.raw;
    // The boundaries themselves are valid samples.
    EXPECT_EQ(s.post(scans, {{"scans", json::array({json::array({{{"bssid", "aa:00"}, {"rss", -120}}, {{"bssid", "aa:01"}, {"rss", 0}}})})}}).status, 200);
}

TEST_F(BadInput, NegativeVarianceOrCount) {
    expect_error(s.post(scans, {{"measurements", {{{"bssid", "aa"}, {"mean", -50}, {"variance", -0.1}, {"count", 3}}}}}), 422,
                 "out_of_range", "negative variance");
    expect_error(s.post(scans, {{"measurements", {{{"bssid", "aa"}, {"mean", -50}, {"variance", 1}, {"count", -3}}}}}), 422,
                 "out_of_range", "negative count");
    expect_error(s.post(scans, {{"measurements", {{{"bssid", "aa"}, {"mean", -50}, {"variance", 1}, {"count", 0}}}}}), 422,
                 "out_of_range", "zero count");
    expect_error(s.post(floors, {{"name", "F"}, {"level", 1}, {"width", -3}, {"height", 3}}), 422, "invalid_field", "negative width");
    expect_error(s.post("/v1/floors/" + std::to_string(h.floor) + "/rooms",
                        {{"name", "R"}, {"rects", {{{"xmin", 5}, {"ymin", 0}, {"xmax", 1}, {"ymax", 1}}}}}),
                 422, "invalid_field", "inverted rectangle");
    EXPECT_TRUE(rp_state().at("measurements").empty());
}

TEST_F(BadInput, OneBadReadingRejectsTheWholeUpload) {
    json scans_body = json::array();
    for (int i = 0; i < 50; ++i) scans_body.push_back(json::array({{{"bssid", "aa:bb:cc:00:00:0" + std::to_string(i % 10)}, {"rss", -60}}}));
    scans_body.push_back(json::array({{{"bssid", "aa:bb:cc:00:00:01"}, {"rss", 12}}}));
    expect_error(s.post(scans, {{"upload_id", "x"}, {"scans", scans_body}}), 422, "out_of_range", "one bad reading");
    const auto state = rp_state();
    EXPECT_TRUE(state.at("measurements").empty());
    EXPECT_EQ(state.at("scans"), 0);
    // The refused upload id was not recorded: the corrected upload applies.
    scans_body.erase(scans_body.end() - 1);
    EXPECT_TRUE(body_of(s.post(scans, {{"upload_id", "x"}, {"scans", scans_body}})).at("applied").get<bool>());
}

TEST_F(BadInput, AFailedImportCreatesNothing) {
    json doc = {{"name", "imported"}, {"rps", json::array()}};
    for (int i = 0; i < 30; ++i) doc["rps"].push_back({{"name", std::string("p").append(std::to_string(i))}, {"x", i}, {"y", 0}});
    doc["rps"].push_back({{"name", "p0"}, {"x", 1}, {"y", 1}});  // duplicate name: fails in the store
    const std::string path = "/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import";
    expect_error(s.post(path, doc), 409, "conflict", "duplicate RP name");
    doc["rps"].back() = {{"name", "p99"}, {"x", 1}, {"y", 1}, {"measurements", {{{"bssid", "aa"}, {"mean", -50}, {"variance", -1}, {"count", 1}}}}};
    expect_error(s.post(path, doc), 422, "out_of_range", "bad measurement at the end");
    EXPECT_EQ(body_of(s.get("/v1/floors/" + std::to_string(h.floor) + "/radiomaps")).at("total"), 1);
}

// Stored counts stop at 2^53 (exact in the merge's doubles): an upload that would pass it
// is refused whole, so whatever is stored can always be exported and imported again.
TEST_F(BadInput, CountsStopAt2To53AndAnExportAlwaysImports) {
    const std::int64_t max_count = std::int64_t{1} << 53;
    auto aggregate = [](std::int64_t count) {
        return json{{"measurements", {{{"bssid", "aa:bb:cc:dd:ee:ff"}, {"mean", -50}, {"variance", 1}, {"count", count}}}}};
    };
    ASSERT_EQ(s.post(scans, aggregate(1'000'000'000)).status, 200);
    ASSERT_EQ(s.post(scans, aggregate(1'000'000'000)).status, 200);
    const json before = rp_state();
    ASSERT_EQ(before.at("measurements").at(0).at("count"), 2'000'000'000);
    expect_error(s.post(scans, aggregate(max_count)), 422, "out_of_range", "count past 2^53");
    expect_error(s.post(scans, aggregate(max_count + 1)), 422, "out_of_range", "one aggregate past 2^53");
    EXPECT_EQ(rp_state(), before);

    json doc = body_of(s.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/export"));
    doc["name"] = "copy";
    const std::string import = "/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import";
    const auto copied = s.post(import, doc);
    EXPECT_EQ(copied.status, 201) << copied.raw;
    doc["name"] = "too many scans";
    doc["rps"][0]["scans"] = max_count + 1;
    expect_error(s.post(import, doc), 422, "out_of_range", "import scans past 2^53");

    // Two aggregates of one AP in one upload are merged first: their sum is checked too.
    json twice = aggregate(max_count);
    twice["measurements"].push_back(twice["measurements"][0]);
    expect_error(s.post(scans, twice), 422, "out_of_range", "one upload's aggregates past 2^53");
    // A new AP first, then one that would pass the bound: the whole upload is refused.
    json two_aps = aggregate(max_count);
    two_aps["measurements"].insert(two_aps["measurements"].begin(),
                                   json{{"bssid", "11:22:33:44:55:66"}, {"mean", -60}, {"variance", 1}, {"count", 5}});
    expect_error(s.post(scans, two_aps), 422, "out_of_range", "second AP past 2^53");
    EXPECT_EQ(rp_state(), before);
    // The RP's scan counter: an imported RP at 2^53 scans takes no more.
    doc["name"] = "full";
    doc["rps"][0]["scans"] = max_count;
    doc["rps"][0]["measurements"] = json::array();
    const auto full = s.post(import, doc);
    ASSERT_EQ(full.status, 201) << full.raw;
    const auto full_rps = body_of(s.get("/v1/radiomaps/" + std::to_string(full.body.at("id").get<std::int64_t>()) + "/rps"));
    const std::string full_scans = "/v1/rps/" + std::to_string(full_rps.at("items").at(0).at("id").get<std::int64_t>()) + "/scans";
    expect_error(s.post(full_scans, {{"scans", one_scan(-50)}}), 422, "out_of_range", "RP scans past 2^53");
}

// An aggregate whose variance no samples in [-120, 0] with that mean could have is refused
// (Bhatia–Davis: at most (0 − mean)(mean + 120)); merged, such aggregates could store what no
// import would take back.
TEST_F(BadInput, AnAggregateNoSamplesCouldHaveIsRefused) {
    auto aggregate = [](double mean, double variance) {
        return json{{"measurements", {{{"bssid", "aa"}, {"mean", mean}, {"variance", variance}, {"count", 3}}}}};
    };
    expect_error(s.post(scans, aggregate(-120, 1)), 422, "out_of_range", "spread at the floor");
    expect_error(s.post(scans, aggregate(-10, 1101)), 422, "out_of_range", "spread past (10)(110)");
    EXPECT_TRUE(rp_state().at("measurements").empty());
    EXPECT_EQ(s.post(scans, aggregate(-60, 3600)).status, 200);  // the widest: half at -120, half at 0
}

// Bytes that are not UTF-8 in the path or the method end up in the error message and the
// access-log line; they must not end the server (nlohmann's dump throws on them).
TEST_F(BadInput, BytesThatAreNotUtf8InThePathOrMethod) {
    expect_error(s.get("/v1/ma%FFps"), 404, "not_found", "percent-encoded 0xFF in the path");
    expect_error(s.get("/v1/maps/1%C0%AF"), 404, "not_found", "overlong encoding in the path");
    locus::tools::BenchConnection c("127.0.0.1", s.port());
    EXPECT_EQ(c.round_trip("G\xffT /v1/maps HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"), 400);
    EXPECT_EQ(c.round_trip("GET /v1/\xfe HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"), 404);
    // The access log is written after the answer: wait for the line, then check the server.
    std::string log = s.log();
    for (int i = 0; i < 100 && log.find("\"status\":400") == std::string::npos; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        log = s.log();
    }
    EXPECT_NE(log.find("\"status\":400"), std::string::npos) << log;
    EXPECT_EQ(s.get("/health").status, 200);
}

// A write without a Content-Length is answered at once (cpp-httplib alone would read until
// the client closes, then answer a bare 400), and the connection stays usable.
TEST_F(BadInput, AWriteWithoutALengthIsRefusedAtOnce) {
    locus::tools::BenchConnection c("127.0.0.1", s.port());
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_EQ(c.round_trip("POST /v1/maps HTTP/1.1\r\nHost: x\r\n\r\n"), 411);
    EXPECT_EQ(c.round_trip("PATCH /v1/maps/" + std::to_string(h.map) + " HTTP/1.1\r\nHost: x\r\n\r\n"), 411);
    EXPECT_EQ(c.round_trip("POST /v1/maps HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: identity\r\n\r\n"), 411);
    EXPECT_EQ(c.round_trip("GET /health HTTP/1.1\r\nHost: x\r\n\r\n"), 200);  // the same connection
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
    expect_error(s.post_raw("/v1/maps", ""), 400, "invalid_json", "an empty body with its length");
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 1);
}

// Room rectangles are coordinates like any other: bounded, and no unknown keys.
TEST_F(BadInput, RoomRectanglesAreCheckedLikeCoordinates) {
    const std::string rooms = "/v1/floors/" + std::to_string(h.floor) + "/rooms";
    expect_error(s.post(rooms, {{"name", "R"}, {"rects", {{{"xmin", -1e308}, {"ymin", 0}, {"xmax", 1}, {"ymax", 1}}}}}), 422,
                 "invalid_field", "huge coordinate");
    expect_error(s.post(rooms, {{"name", "R"}, {"rects", {{{"xmin", 0}, {"ymin", 0}, {"xmax", 1}, {"ymax", 1}, {"z", 1}}}}}), 422,
                 "invalid_field", "unknown key in a rectangle");
    EXPECT_EQ(body_of(s.get(rooms)).at("total"), 0);
}

TEST_F(BadInput, UnknownIds) {
    expect_error(s.get("/v1/floors/999999"), 404, "not_found", "unknown floor");
    expect_error(s.get("/v1/rps/99999999999999999999999"), 404, "not_found", "id beyond int64");
    expect_error(s.get("/v1/maps/0"), 404, "not_found", "id 0");
    expect_error(s.post("/v1/buildings/4242/floors", {{"name", "F"}, {"level", 0}, {"width", 1}, {"height", 1}}), 404, "not_found",
                 "unknown parent");
    expect_error(s.get("/v1/buildings/4242/floors"), 404, "not_found", "list under unknown parent");
    expect_error(s.post("/v1/rps/4242/scans", {{"scans", one_scan(-50)}}), 404, "not_found", "scans to unknown rp");
    expect_error(s.patch("/v1/pois/4242", {{"name", "x"}}), 404, "not_found", "patch unknown");
    expect_error(s.del("/v1/rooms/4242"), 404, "not_found", "delete unknown");
    expect_error(s.get("/v1/radiomaps/4242/export"), 404, "not_found", "export unknown");
    expect_error(s.post("/v1/radiomaps/4242/localize", {{"scans", one_scan(-50)}}), 404, "not_found", "localize unknown");
    expect_error(s.get("/v1/no-such-thing"), 404, "not_found", "unknown route");
}

TEST_F(BadInput, DuplicateNames) {
    expect_error(s.post("/v1/maps", {{"name", "HQ"}}), 409, "conflict", "duplicate map");
    expect_error(s.post("/v1/radiomaps/" + std::to_string(h.radiomap) + "/rps", {{"name", "rp-1"}, {"x", 0}, {"y", 0}}), 409,
                 "conflict", "duplicate rp");
    const auto other = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps", {{"name", "second"}});
    ASSERT_EQ(other.status, 201);
    EXPECT_EQ(s.post("/v1/radiomaps/" + std::to_string(other.body.at("id").get<long long>()) + "/rps",
                     {{"name", "rp-1"}, {"x", 0}, {"y", 0}})
                  .status,
              201)
        << "names are unique per radio map, not globally";
    const auto m2 = s.post("/v1/maps", {{"name", "Second"}});
    expect_error(s.patch("/v1/maps/" + std::to_string(m2.body.at("id").get<long long>()), {{"name", "HQ"}}), 409, "conflict",
                 "rename onto an existing name");
}

TEST_F(BadInput, BadPagination) {
    for (const std::string q : {"limit=0", "limit=-1", "limit=abc", "limit=100000", "offset=-5", "offset=1.5"})
        expect_error(s.get("/v1/maps?" + q), 400, "invalid_query", q);
}

TEST_F(BadInput, HugeBodiesAreRefused) {
    const auto r = s.post_raw("/v1/maps", name_body(9u * 1024u * 1024u));
    if (r.status != 0) expect_error(r, 413, "payload_too_large", "9 MiB body");
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 1);
}

// Millions of empty scans just under the body limit: each once cost an empty vector while the
// body was read (some 110 MiB a body); the parse now stops at the 1,001st, a plain 422.
TEST_F(BadInput, MillionsOfEmptyScansAreACheapRefusal) {
    std::string body = R"({"scans":[[])";
    while (body.size() < 7u * 1024u * 1024u) body.append(",[]");
    body.append("]}");
    const auto r = s.post_raw("/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize", body);
    expect_error(r, 422, "out_of_range", "2.4 million empty scans");
    EXPECT_NE(r.raw.find("more than 1000 scans"), std::string::npos) << r.raw;
}

TEST(ServerLimits, BodyLimitIsConfigurable) {
    ServerProcess s({"--max-body-bytes", "1024"});
    const auto r = s.post_raw("/v1/maps", name_body(2000));
    if (r.status != 0) expect_error(r, 413, "payload_too_large", "2 kB body over a 1 kB limit");
    EXPECT_EQ(s.post("/v1/maps", {{"name", "small"}}).status, 201);
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 1);
}

TEST(ServerAuth, WritesNeedTheKeyReadsDoNot) {
    ServerProcess s({"--api-key", "s3cret"});
    expect_error(s.post("/v1/maps", {{"name", "M"}}), 401, "unauthorized", "no key");
    s.set_api_key("wrong");
    expect_error(s.post("/v1/maps", {{"name", "M"}}), 401, "unauthorized", "wrong key");
    s.set_api_key("s3cret");
    const auto created = s.post("/v1/maps", {{"name", "M"}});
    ASSERT_EQ(created.status, 201);
    s.set_api_key("");
    EXPECT_EQ(s.get("/v1/maps").status, 200);
    const auto id = std::to_string(created.body.at("id").get<long long>());
    expect_error(s.del("/v1/maps/" + id), 401, "unauthorized", "delete without key");
    expect_error(s.patch("/v1/maps/" + id, {{"name", "N"}}), 401, "unauthorized", "patch without key");
    // Localizing is a read: it is answered (here 404: the map has no radio map 1) without a key.
    EXPECT_NE(s.post("/v1/radiomaps/1/localize", {{"scans", one_scan(-50)}}).status, 401);
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 1);
}

TEST(ServerAuth, KeyCanComeFromTheEnvironment) {
    setenv("LOCUS_API_KEY", "from-env", 1);
    ServerProcess s;
    unsetenv("LOCUS_API_KEY");
    expect_error(s.post("/v1/maps", {{"name", "M"}}), 401, "unauthorized", "no key");
    s.set_api_key("from-env");
    EXPECT_EQ(s.post("/v1/maps", {{"name", "M"}}).status, 201);
}

TEST_F(BadInput, EveryMissingFieldIsNamedAtOnce) {
    const auto r = s.post(floors, json::object());
    expect_error(r, 422, "invalid_field", "empty floor");
    EXPECT_EQ(r.body["error"]["message"], "missing fields 'name', 'level', 'width' and 'height'") << r.raw;
    const auto one = s.post(floors, {{"name", "F"}, {"level", 1}, {"width", 10}});
    EXPECT_EQ(one.body["error"]["message"], "missing field 'height'") << one.raw;
    const auto poi = s.post("/v1/floors/" + std::to_string(h.floor) + "/pois", {{"name", "P"}});
    EXPECT_EQ(poi.body["error"]["message"], "missing fields 'x' and 'y'") << poi.raw;
    EXPECT_EQ(body_of(s.get(floors)).at("total"), 1);
}

}  // namespace
}  // namespace server_bad_input_test
