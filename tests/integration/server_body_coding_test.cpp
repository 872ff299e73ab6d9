// Request bodies with a Content-Encoding: limited by their decoded size (413 naming the limit,
// with the server's memory bounded), decoded before any handler reads them, and refused with
// 415 where the coding or the route does not take one. Nothing of a refused body is stored.
#include <httplib.h>
#include <gtest/gtest.h>

#include <string>

#include "compressed_body.hpp"
#include "proc_status.hpp"
#include "hierarchy.hpp"
#include "raw_connection.hpp"
#include "server_process.hpp"

namespace server_body_coding_test {
namespace {

using locus::testing::RawConnection;
using locus::testing::Response;
using locus::testing::ServerProcess;
using locus::tools::Wrapper;
using locus::testing::body_of;
using locus::tools::compress;
using locus::tools::compress_stream;
using nlohmann::json;

Response post_encoded(const ServerProcess& s, const std::string& path, const std::string& body, const std::string& coding) {
    auto c = locus::testing::client(s.port());
    return locus::testing::to_response(c.Post(path, {{"Content-Encoding", coding}}, body, "application/json"));
}

// The server's peak resident memory so far (VmHWM), in bytes.
long long peak_rss(const ServerProcess& s) {
    const long long kb = locus::tools::proc_status_kb(s.pid(), "VmHWM:");
    return kb < 0 ? -1 : kb * 1024;
}

void expect_error(const Response& r, int status, const std::string& code, const std::string& says = {}) {
    EXPECT_EQ(r.status, status) << r.raw;
    ASSERT_TRUE(r.body.is_object()) << r.raw;
    EXPECT_EQ(r.body["error"]["code"], code) << r.raw;
    if (!says.empty()) {
        EXPECT_NE(r.raw.find(says), std::string::npos) << "the message should say '" << says << "': " << r.raw;
    }
}

const std::string kScan = R"([[{"bssid":"00:1a:2b:00:00:01","rss":-52},{"bssid":"00:1a:2b:00:00:02","rss":-71}]])";

struct BodyCoding : ::testing::Test {
    ServerProcess s;
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    std::int64_t rp = locus::testing::make_rp(s, h.radiomap, "rp-1", 2.0, 3.0);
    std::string scans = "/v1/rps/" + std::to_string(rp) + "/scans";
    std::string localize = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize";

    json measurements() { return body_of(s.get("/v1/rps/" + std::to_string(rp))).at("measurements"); }
    void TearDown() override { EXPECT_EQ(s.get("/health").status, 200) << "the server must keep serving"; }
};

TEST_F(BodyCoding, GzipAndDeflateBodiesAreDecodedBeforeTheRouteReadsThem) {
    const std::string upload = R"({"upload_id":"u1","scans":)" + kScan + "}";
    ASSERT_EQ(post_encoded(s, scans, compress(upload), "gzip").status, 200);
    ASSERT_EQ(measurements().size(), 2u);

    const std::string query = R"({"algorithm":"wknn","scans":)" + kScan + "}";
    const Response plain = s.post_raw(localize, query);
    ASSERT_EQ(plain.status, 200) << plain.raw;
    for (const auto& [coding, wrapper] : {std::pair{"gzip", Wrapper::gzip}, std::pair{"x-gzip", Wrapper::gzip},
                                          std::pair{"deflate", Wrapper::zlib}, std::pair{"DEFLATE", Wrapper::raw}}) {
        const Response r = post_encoded(s, localize, compress(query, wrapper), coding);
        EXPECT_EQ(r.status, 200) << coding << ": " << r.raw;
        EXPECT_EQ(r.body.at("x"), plain.body.at("x")) << coding;
        EXPECT_EQ(r.body.at("rps"), plain.body.at("rps")) << coding;
    }
    EXPECT_EQ(post_encoded(s, localize, query, "identity").status, 200);
}

TEST_F(BodyCoding, ABombIsRefusedByItsDecodedSizeAndTheMemoryStaysBounded) {
    // 512 MiB of whitespace inside a valid localize request, gzip'd to about 500 KB.
    const std::string bomb = compress_stream(R"({"algorithm":"wknn","scans":)" + kScan + ",\"x\":\"", ' ', 512u << 20, "\"}");
    ASSERT_LT(bomb.size(), 1u << 20);
    const long long before = peak_rss(s);
    ASSERT_GT(before, 0);
    for (const std::string& path : {localize, scans}) {
        const Response r = post_encoded(s, path, bomb, "gzip");
        expect_error(r, 413, "payload_too_large", std::to_string(8u << 20));
        EXPECT_NE(r.raw.find("decoded"), std::string::npos) << r.raw;
    }
    // Decoding stops at the 8 MiB limit: the peak grows by a few times that, never by the
    // 512 MiB the body inflates to.
    EXPECT_LT(peak_rss(s) - before, 64ll << 20) << "peak resident memory grew from " << before;
    EXPECT_TRUE(measurements().empty());
}

TEST(BodyCodingLimit, TheRoutesLimitAppliesToTheDecodedBody) {
    ServerProcess s({"--max-body-bytes", "4096"});
    const std::string big = R"({"name":"m")" + std::string(5000, ' ') + "}";
    ASSERT_LT(compress(big).size(), 4096u);
    expect_error(post_encoded(s, "/v1/maps", compress(big), "gzip"), 413, "payload_too_large", "4096");
    EXPECT_EQ(body_of(s.get("/v1/maps")).at("total"), 0);
    const std::string small = R"({"name":"m")" + std::string(3000, ' ') + "}";
    EXPECT_EQ(post_encoded(s, "/v1/maps", compress(small), "gzip").status, 201);
}

TEST_F(BodyCoding, OtherCodingsAre415AndNothingIsStored) {
    const std::string upload = R"({"upload_id":"u2","scans":)" + kScan + "}";
    for (const char* coding : {"br", "compress", "zstd", "gzip, gzip", "gzip;q=1"})
        expect_error(post_encoded(s, scans, compress(upload), coding), 415, "unsupported_encoding", "gzip, deflate");
    // Two Content-Encoding lines are a body coded twice.
    RawConnection c(s.port());
    ASSERT_TRUE(c.send(locus::testing::raw_post(scans, compress(compress(upload)),
                                                "Content-Encoding: gzip\r\nContent-Encoding: gzip\r\n")));
    const auto twice = c.read_answer();
    ASSERT_TRUE(twice.has_value());
    EXPECT_EQ(twice->status, 415) << twice->body;
    EXPECT_TRUE(measurements().empty());
}

TEST_F(BodyCoding, APlanImageTakesNoCoding) {
    auto c = locus::testing::client(s.port());
    const auto r = locus::testing::to_response(c.Put("/v1/floors/" + std::to_string(h.floor) + "/image",
                                                     {{"Content-Encoding", "gzip"}}, compress("\x89PNG"), "image/png"));
    expect_error(r, 415, "unsupported_encoding", "without a Content-Encoding");
    EXPECT_EQ(s.get("/v1/floors/" + std::to_string(h.floor) + "/image").status, 404);
}

TEST_F(BodyCoding, ADamagedBodyIs400) {
    const std::string upload = compress(R"({"upload_id":"u3","scans":)" + kScan + "}");
    expect_error(post_encoded(s, scans, upload.substr(0, upload.size() / 2), "gzip"), 400, "bad_encoding");
    expect_error(post_encoded(s, scans, "plain text, not gzip", "gzip"), 400, "bad_encoding");
    EXPECT_TRUE(measurements().empty());
}

TEST_F(BodyCoding, AnUnacceptedCodingIsRefusedBeforeTheBodyIsSent) {
    // With Expect: 100-continue the client waits for the go-ahead; it gets the 415 instead.
    RawConnection c(s.port());
    ASSERT_TRUE(c.send("POST " + scans + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                       "Content-Length: 100000\r\nContent-Encoding: br\r\nExpect: 100-continue\r\n\r\n"));
    const auto answer = c.read_answer();
    ASSERT_TRUE(answer.has_value());
    EXPECT_EQ(answer->status, 415) << answer->body;
}

TEST_F(BodyCoding, AChunkedGzipBodyIsDecoded) {
    const std::string upload = compress(R"({"upload_id":"u4","scans":)" + kScan + "}");
    RawConnection c(s.port());
    ASSERT_TRUE(c.send(locus::testing::raw_chunked_post(scans, upload, 7, "Content-Encoding: gzip\r\n")));
    const auto answer = c.read_answer();
    ASSERT_TRUE(answer.has_value());
    EXPECT_EQ(answer->status, 200) << answer->body;
    EXPECT_EQ(measurements().size(), 2u);
}

}  // namespace
}  // namespace server_body_coding_test
