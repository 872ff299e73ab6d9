#include "test_images.hpp"

#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace locus::testing {

std::vector<std::uint8_t> image_pattern(unsigned w, unsigned h, int channels) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h * static_cast<std::size_t>(channels));
    for (std::size_t i = 0; i < px.size(); ++i) px[i] = static_cast<std::uint8_t>((i * 13 + (i / (w ? w : 1)) * 7) % 256);
    return px;
}

std::string png_bytes(unsigned w, unsigned h, png_uint_32 format, const std::vector<std::uint8_t>& pixels) {
    png_image image;
    std::memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = w;
    image.height = h;
    image.format = format;
    if (pixels.size() != PNG_IMAGE_SIZE(image)) throw std::runtime_error("png_bytes: pixel count does not match the format");
    png_alloc_size_t size = 0;
    png_image_write_to_memory(&image, nullptr, &size, 0, pixels.data(), 0, nullptr);
    std::string out(size, '\0');
    if (!png_image_write_to_memory(&image, out.data(), &size, 0, pixels.data(), 0, nullptr))
        throw std::runtime_error(std::string("libpng: ") + image.message);
    out.resize(size);
    return out;
}

std::string jpeg_bytes(unsigned w, unsigned h, const std::vector<std::uint8_t>& pixels, const JpegOptions& o) {
    const std::size_t stride = static_cast<std::size_t>(w) * static_cast<std::size_t>(o.components);
    if (pixels.size() != stride * h) throw std::runtime_error("jpeg_bytes: pixel count does not match the size");
    jpeg_compress_struct info;
    jpeg_error_mgr err;
    info.err = jpeg_std_error(&err);
    jpeg_create_compress(&info);
    unsigned char* buf = nullptr;
    unsigned long size = 0;
    jpeg_mem_dest(&info, &buf, &size);
    info.image_width = w;
    info.image_height = h;
    info.input_components = o.components;
    info.in_color_space = o.space;
    jpeg_set_defaults(&info);
    jpeg_set_quality(&info, o.quality, TRUE);
    if (o.progressive) jpeg_simple_progression(&info);
    jpeg_start_compress(&info, TRUE);
    while (info.next_scanline < h) {
        JSAMPROW row = const_cast<std::uint8_t*>(pixels.data()) + info.next_scanline * stride;
        jpeg_write_scanlines(&info, &row, 1);
    }
    jpeg_finish_compress(&info);
    jpeg_destroy_compress(&info);
    std::string out(reinterpret_cast<const char*>(buf), size);
    std::free(buf);
    return out;
}

}  // namespace locus::testing
