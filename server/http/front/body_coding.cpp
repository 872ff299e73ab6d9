#include "http/front/body_coding.hpp"

#include <strings.h>
#include <zlib.h>

#include <algorithm>

namespace locus::http {

std::optional<BodyCoding> parse_body_coding(std::string_view header) {
    const auto first = header.find_first_not_of(" \t");
    if (first == std::string_view::npos) return BodyCoding::identity;
    const auto last = header.find_last_not_of(" \t");
    const std::string name(header.substr(first, last - first + 1));
    if (strcasecmp(name.c_str(), "identity") == 0) return BodyCoding::identity;
    if (strcasecmp(name.c_str(), "gzip") == 0 || strcasecmp(name.c_str(), "x-gzip") == 0) return BodyCoding::gzip;
    if (strcasecmp(name.c_str(), "deflate") == 0) return BodyCoding::deflate;
    return std::nullopt;
}

DecodedBody decode_body(std::string_view encoded, BodyCoding coding, std::uint64_t limit) {
    DecodedBody out;
    if (coding == BodyCoding::identity) {
        if (encoded.size() > limit) out.status = DecodedBody::Status::too_large;
        else out.body.assign(encoded);
        return out;
    }
    auto corrupt = [&](std::string why) {
        out.status = DecodedBody::Status::corrupt;
        out.body.clear();
        out.problem = std::move(why);
        return out;
    };
    z_stream z{};
    // 16 + 15: a gzip wrapper only; 15: a zlib wrapper, which is what HTTP's "deflate" names
    // (RFC 9110 §8.4.1.2), although some clients send a raw deflate stream: tried below.
    int window = coding == BodyCoding::gzip ? 16 + MAX_WBITS : MAX_WBITS;
    bool retried_raw = false;
    if (inflateInit2(&z, window) != Z_OK) return corrupt("the decoder could not start");
    constexpr std::size_t step = 64 * 1024;
    for (;;) {
        z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(encoded.data()));
        z.avail_in = static_cast<uInt>(encoded.size());
        out.body.clear();
        int rc = Z_OK;
        while (rc == Z_OK) {
            if (out.body.size() > limit) break;
            const std::size_t have = out.body.size();
            out.body.resize(have + step);
            z.next_out = reinterpret_cast<Bytef*>(out.body.data() + have);
            z.avail_out = static_cast<uInt>(step);
            rc = inflate(&z, Z_NO_FLUSH);
            out.body.resize(have + (step - z.avail_out));
            if (rc == Z_BUF_ERROR && z.avail_in == 0) break;  // the input ended before the stream did
        }
        if (out.body.size() > limit) {
            inflateEnd(&z);
            out.status = DecodedBody::Status::too_large;
            out.body.clear();
            out.body.shrink_to_fit();
            return out;
        }
        if (rc == Z_DATA_ERROR && coding == BodyCoding::deflate && !retried_raw && out.body.empty()) {
            retried_raw = true;  // no zlib header: a raw deflate stream
            window = -MAX_WBITS;
            inflateEnd(&z);
            if (inflateInit2(&z, window) != Z_OK) return corrupt("the decoder could not start");
            continue;
        }
        inflateEnd(&z);
        if (rc == Z_STREAM_END) {
            if (z.avail_in != 0) return corrupt("bytes follow the end of the compressed stream");
            return out;
        }
        if (rc == Z_DATA_ERROR) return corrupt(std::string("the compressed body is damaged") + (z.msg ? std::string(": ") + z.msg : ""));
        return corrupt("the compressed body ends before its stream does");
    }
}

}  // namespace locus::http
