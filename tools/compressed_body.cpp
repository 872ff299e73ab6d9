#include "compressed_body.hpp"

#include <zlib.h>

#include <algorithm>
#include <stdexcept>

namespace locus::tools {

std::string compress_stream(std::string_view prefix, char fill, std::size_t repeat, std::string_view suffix, Wrapper wrapper) {
    z_stream z{};
    const int bits = wrapper == Wrapper::gzip ? 16 + MAX_WBITS : wrapper == Wrapper::zlib ? MAX_WBITS : -MAX_WBITS;
    if (deflateInit2(&z, 9, Z_DEFLATED, bits, 9, Z_DEFAULT_STRATEGY) != Z_OK) throw std::runtime_error("zlib: deflateInit2 failed");
    std::string out;
    char buf[64 * 1024];
    auto feed = [&](std::string_view in, int flush) {
        z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
        z.avail_in = static_cast<uInt>(in.size());
        do {
            z.next_out = reinterpret_cast<Bytef*>(buf);
            z.avail_out = sizeof buf;
            deflate(&z, flush);
            out.append(buf, sizeof buf - z.avail_out);
        } while (z.avail_out == 0);
    };
    feed(prefix, Z_NO_FLUSH);
    const std::string block(1 << 20, fill);
    for (std::size_t left = repeat; left > 0;) {
        const std::size_t n = std::min(left, block.size());
        feed(std::string_view(block).substr(0, n), Z_NO_FLUSH);
        left -= n;
    }
    feed(suffix, Z_FINISH);
    deflateEnd(&z);
    return out;
}

}  // namespace locus::tools
