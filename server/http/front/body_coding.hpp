#pragma once
// Request bodies sent with a Content-Encoding (RFC 9110 §8.4): which codings a route takes,
// and decoding one under a limit on the decoded size.
//
// cpp-httplib, built with zlib and Brotli as Debian builds it, inflates a compressed body
// into memory with no bound: the body limit counted the compressed bytes, so a 510 KB gzip
// body became 512 MiB. The connection layer (front.cpp) therefore takes the Content-Encoding
// header away before cpp-httplib reads the body, refuses a coding the route does not take
// with 415, and decodes the body itself here, in bounded steps, stopping at the first byte
// past the route's limit.
//
// Cost: one pass of zlib's inflate (about 300 MB/s of output on one core), output grown in
// 64 KiB steps; memory is the compressed body plus at most `limit` decoded bytes.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace locus::http {

enum class BodyCoding { identity, gzip, deflate };

// The coding a Content-Encoding value names (case-insensitive; `x-gzip` is gzip, as RFC 9110
// asks), or nullopt for anything else: Brotli, compress, zstd, or a list of several codings
// (a body compressed twice has no use but to multiply the decoded size).
std::optional<BodyCoding> parse_body_coding(std::string_view header);

struct DecodedBody {
    enum class Status { ok, too_large, corrupt } status = Status::ok;
    std::string body;     // the decoded body (status ok), else empty
    std::string problem;  // why it is corrupt
};

// Decodes `encoded` (a gzip or zlib stream, as `coding` says) into at most `limit` bytes.
// Over the limit: too_large, found without decoding more than limit + 64 KiB. A stream that
// ends early, has trailing bytes or a bad checksum: corrupt. identity returns `encoded`.
DecodedBody decode_body(std::string_view encoded, BodyCoding coding, std::uint64_t limit);

}  // namespace locus::http
