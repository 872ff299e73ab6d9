#pragma once
// What a plan image's bytes are: read with libpng and libjpeg (never by hand), so a body
// that is not the image its Content-Type says is refused before anything is stored.
#include <cstdint>
#include <string>
#include <string_view>

namespace locus::http {

inline constexpr std::uint64_t kMaxImageBytes = 20u * 1024u * 1024u;  // 20 MiB, the bound
inline constexpr std::int64_t kMaxImageSide = 20000;                  // pixels, either side

struct ImageHeader {
    std::string content_type;  // "image/png" or "image/jpeg"
    std::int64_t width_px = 0, height_px = 0;
};

// The media type of a Content-Type header without parameters, lower-cased ("image/png").
std::string media_type(std::string_view content_type);

// ApiError 415 unsupported_media_type unless `type` is image/png or image/jpeg.
void require_image_type(const std::string& type);

// Reads `bytes` as `type` ("image/png" or "image/jpeg"; anything else: ApiError 415
// unsupported_media_type). Bytes of the other format, a corrupt or truncated file, zero or
// more than kMaxImageSide pixels a side: ApiError 422 invalid_image saying which. A PNG is
// decoded row by row to its IEND chunk (every CRC and the compressed data checked, one row in
// memory); a JPEG is decoded at 1/8 scale to its last scanline, so a cut-off or corrupt
// upload is caught without holding the full image in memory. At most two decode at a time.
ImageHeader read_image_header(std::string_view bytes, const std::string& type);

}  // namespace locus::http
