#include "image_file.hpp"

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include <jpeglib.h>
#include <png.h>

#include "survey_connect.hpp"

namespace locus::tools {

namespace {

// Larger images are refused before their pixels are allocated: 20,000 × 20,000 px is a
// 700 m building at 28 px/m, far past what a plan may cover.
constexpr long long kMaxPixels = 400'000'000LL;

void check_size(const std::string& path, long long w, long long h) {
    if (w <= 0 || h <= 0) throw std::runtime_error("'" + path + "' has no pixels");
    if (w * h > kMaxPixels)
        throw std::runtime_error("'" + path + "' is " + std::to_string(w) + " × " + std::to_string(h) +
                                 " pixels, more than " + std::to_string(kMaxPixels) + " this command reads");
}

imaging::GreyImage read_png(const std::string& path, const std::string& bytes) {
    png_image img;
    std::memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&img, bytes.data(), bytes.size()))
        throw std::runtime_error("'" + path + "' is not a readable PNG: " + img.message);
    // Free libpng's state on every path out.
    std::unique_ptr<png_image, void (*)(png_image*)> guard(&img, png_image_free);
    check_size(path, img.width, img.height);
    img.format = PNG_FORMAT_GRAY;  // libpng converts colour and composes alpha over the background
    imaging::GreyImage out;
    out.width = static_cast<int>(img.width);
    out.height = static_cast<int>(img.height);
    out.pixels.resize(PNG_IMAGE_SIZE(img));
    png_color white{255, 255, 255};
    if (!png_image_finish_read(&img, &white, out.pixels.data(), 0, nullptr))
        throw std::runtime_error("'" + path + "' is not a readable PNG: " + img.message);
    guard.release();
    return out;
}

struct JpegFailure {
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void jpeg_fail(j_common_ptr cinfo) {
    auto* f = reinterpret_cast<JpegFailure*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, f->message);
    std::longjmp(f->jump, 1);
}

// libjpeg reports errors by longjmp: nothing with a destructor lives between setjmp and the
// calls that may jump, so the output buffer is sized only after the header is read.
imaging::GreyImage read_jpeg(const std::string& path, const std::string& bytes) {
    jpeg_decompress_struct cinfo;
    JpegFailure failure;
    cinfo.err = jpeg_std_error(&failure.mgr);
    failure.mgr.error_exit = jpeg_fail;
    imaging::GreyImage out;
    if (setjmp(failure.jump)) {
        jpeg_destroy_decompress(&cinfo);
        throw std::runtime_error("'" + path + "' is not a readable JPEG: " + failure.message);
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&cinfo, TRUE);
    cinfo.out_color_space = JCS_GRAYSCALE;
    jpeg_start_decompress(&cinfo);
    const long long w = cinfo.output_width, h = cinfo.output_height;
    if (w <= 0 || h <= 0 || w * h > kMaxPixels) {
        jpeg_destroy_decompress(&cinfo);
        check_size(path, w, h);
    }
    out.width = static_cast<int>(w);
    out.height = static_cast<int>(h);
    out.pixels.resize(static_cast<std::size_t>(w * h));
    while (cinfo.output_scanline < cinfo.output_height) {
        JSAMPROW row = out.pixels.data() + static_cast<std::size_t>(cinfo.output_scanline) * static_cast<std::size_t>(w);
        jpeg_read_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    return out;
}

}  // namespace

imaging::GreyImage read_grey_image(const std::string& path) {
    const std::string bytes = read_file(path);
    static const unsigned char png_magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (bytes.size() >= 8 && std::memcmp(bytes.data(), png_magic, 8) == 0) return read_png(path, bytes);
    if (bytes.size() >= 3 && static_cast<unsigned char>(bytes[0]) == 0xff && static_cast<unsigned char>(bytes[1]) == 0xd8 &&
        static_cast<unsigned char>(bytes[2]) == 0xff)
        return read_jpeg(path, bytes);
    throw std::runtime_error("'" + path + "' is neither a PNG nor a JPEG image");
}

}  // namespace locus::tools
