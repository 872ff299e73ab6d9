#pragma once
// Request bodies compressed as a client would send them (Content-Encoding gzip or deflate),
// with zlib's own deflate: `locus bench abuse` sends decompression bombs with it, and the
// tests of the server's decoding (which inflates with zlib) compress their bodies with it.
#include <cstddef>
#include <string>
#include <string_view>

namespace locus::tools {

enum class Wrapper { gzip, zlib, raw };  // gzip; deflate as HTTP names it (zlib); a bare deflate stream

// `prefix`, then `repeat` copies of `fill`, then `suffix`, compressed at level 9 without ever
// holding the uncompressed bytes: 512 MiB of spaces compress to about 500 KB in ~1 s.
std::string compress_stream(std::string_view prefix, char fill, std::size_t repeat, std::string_view suffix,
                            Wrapper wrapper = Wrapper::gzip);

inline std::string compress(std::string_view body, Wrapper wrapper = Wrapper::gzip) {
    return compress_stream(body, ' ', 0, "", wrapper);
}

}  // namespace locus::tools
