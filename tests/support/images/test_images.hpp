#pragma once
// PNG and JPEG bytes for the tests and benchmarks of plan images and drawings, written with
// libpng and libjpeg: the same libraries the server and the CLI read them with.
#include <cstdint>
#include <cstdio>  // jpeglib.h needs FILE declared first
#include <string>
#include <vector>

#include <jpeglib.h>
#include <png.h>

namespace locus::testing {

// A deterministic, non-flat pattern of w × h pixels with `channels` bytes each.
std::vector<std::uint8_t> image_pattern(unsigned w, unsigned h, int channels);

// `pixels` (w × h, as many bytes per pixel as `format` says: PNG_FORMAT_GRAY, _RGB, _RGBA…)
// encoded as PNG. Throws std::runtime_error when libpng refuses.
std::string png_bytes(unsigned w, unsigned h, png_uint_32 format, const std::vector<std::uint8_t>& pixels);

struct JpegOptions {
    J_COLOR_SPACE space = JCS_GRAYSCALE;
    int components = 1;
    bool progressive = false;
    int quality = 75;
};
// `pixels` (w × h × components bytes) encoded as JPEG.
std::string jpeg_bytes(unsigned w, unsigned h, const std::vector<std::uint8_t>& pixels, const JpegOptions& options = {});

}  // namespace locus::testing
