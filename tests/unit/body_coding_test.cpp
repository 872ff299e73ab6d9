// Request bodies with a Content-Encoding: which codings are taken, and decoding under a limit
// on the decoded size (server/http/front/body_coding.hpp).
#include "http/front/body_coding.hpp"

#include <gtest/gtest.h>

#include <string>

#include "compressed_body.hpp"

namespace body_coding_test {
namespace {

using locus::http::BodyCoding;
using locus::http::DecodedBody;
using locus::http::decode_body;
using locus::http::parse_body_coding;
using locus::tools::Wrapper;
using locus::tools::compress;
using locus::tools::compress_stream;

TEST(BodyCoding, NamesAreReadAsRfc9110Spells) {
    EXPECT_EQ(parse_body_coding("gzip"), BodyCoding::gzip);
    EXPECT_EQ(parse_body_coding(" GZip "), BodyCoding::gzip);
    EXPECT_EQ(parse_body_coding("x-gzip"), BodyCoding::gzip);
    EXPECT_EQ(parse_body_coding("deflate"), BodyCoding::deflate);
    EXPECT_EQ(parse_body_coding("identity"), BodyCoding::identity);
    EXPECT_EQ(parse_body_coding(""), BodyCoding::identity);
    for (const char* refused : {"br", "compress", "zstd", "gzip, gzip", "gzip,deflate", "gzip;q=1", "bzip2"})
        EXPECT_FALSE(parse_body_coding(refused).has_value()) << refused;
}

TEST(BodyCoding, GzipZlibAndRawDeflateDecode) {
    const std::string body = R"({"scans":[[{"bssid":"00:1a:2b:00:00:01","rss":-52}]]})";
    for (const auto& [coding, wrapper] : {std::pair{BodyCoding::gzip, Wrapper::gzip}, std::pair{BodyCoding::deflate, Wrapper::zlib},
                                         std::pair{BodyCoding::deflate, Wrapper::raw}}) {
        const DecodedBody d = decode_body(compress(body, wrapper), coding, 1024);
        EXPECT_EQ(d.status, DecodedBody::Status::ok) << d.problem;
        EXPECT_EQ(d.body, body);
    }
    // gzip's wrapper is not taken for deflate's, nor the other way round.
    EXPECT_EQ(decode_body(compress(body, Wrapper::zlib), BodyCoding::gzip, 1024).status, DecodedBody::Status::corrupt);
    EXPECT_EQ(decode_body(compress(body, Wrapper::gzip), BodyCoding::deflate, 1024).status, DecodedBody::Status::corrupt);
}

TEST(BodyCoding, TheLimitCountsDecodedBytes) {
    const std::string exact = compress_stream("", 'a', 100'000, "");
    EXPECT_EQ(decode_body(exact, BodyCoding::gzip, 100'000).status, DecodedBody::Status::ok);
    EXPECT_EQ(decode_body(exact, BodyCoding::gzip, 100'000).body.size(), 100'000u);
    const DecodedBody over = decode_body(exact, BodyCoding::gzip, 99'999);
    EXPECT_EQ(over.status, DecodedBody::Status::too_large);
    EXPECT_TRUE(over.body.empty());
    // identity is limited too.
    EXPECT_EQ(decode_body(std::string(11, 'x'), BodyCoding::identity, 10).status, DecodedBody::Status::too_large);
    EXPECT_EQ(decode_body(std::string(10, 'x'), BodyCoding::identity, 10).body, std::string(10, 'x'));
}

TEST(BodyCoding, ABombIsRefusedWithoutInflatingIt) {
    // 512 MiB of spaces in half a megabyte: refused at the 8 MiB limit. Decoding it whole
    // would hold 512 MiB; the answer comes with at most the limit in memory.
    const std::string bomb = compress_stream(R"({"scans":[[{"bssid":"a","rss":-50}]],"pad":")", ' ', 512u << 20, "\"}");
    ASSERT_LT(bomb.size(), 1u << 20);
    const DecodedBody d = decode_body(bomb, BodyCoding::gzip, 8u << 20);
    EXPECT_EQ(d.status, DecodedBody::Status::too_large);
    EXPECT_LE(d.body.capacity(), 8u << 20);
}

TEST(BodyCoding, DamagedStreamsAreCorrupt) {
    const std::string good = compress(R"({"name":"a map with a long enough name to compress"})");
    EXPECT_EQ(decode_body(good.substr(0, good.size() - 6), BodyCoding::gzip, 1024).status, DecodedBody::Status::corrupt);
    EXPECT_EQ(decode_body(good + "junk", BodyCoding::gzip, 1024).status, DecodedBody::Status::corrupt);
    std::string bad_crc = good;
    bad_crc[bad_crc.size() - 5] ^= 0x55;  // the CRC-32 in gzip's trailer
    const DecodedBody d = decode_body(bad_crc, BodyCoding::gzip, 1024);
    EXPECT_EQ(d.status, DecodedBody::Status::corrupt);
    EXPECT_FALSE(d.problem.empty());
    EXPECT_EQ(decode_body("", BodyCoding::gzip, 1024).status, DecodedBody::Status::corrupt);
    EXPECT_EQ(decode_body("not compressed at all", BodyCoding::deflate, 1024).status, DecodedBody::Status::corrupt);
}

}  // namespace
}  // namespace body_coding_test
