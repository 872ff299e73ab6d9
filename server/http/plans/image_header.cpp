#include "http/plans/image_header.hpp"

// jpeglib.h before jerror.h, which names libjpeg's messages (JWRN_JPEG_EOF).
// clang-format off
#include <cstdio>
#include <jpeglib.h>
#include <jerror.h>
// clang-format on
#include <png.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <semaphore>
#include <cstring>
#include <vector>

#include "http/api_error.hpp"

namespace locus::http {

namespace {

ApiError invalid_image(const std::string& message) { return {422, "invalid_image", message}; }

bool looks_like_png(std::string_view b) {
    return b.size() >= 8 && png_sig_cmp(reinterpret_cast<png_const_bytep>(b.data()), 0, 8) == 0;
}
bool looks_like_jpeg(std::string_view b) {
    return b.size() >= 3 && static_cast<unsigned char>(b[0]) == 0xFF && static_cast<unsigned char>(b[1]) == 0xD8 &&
           static_cast<unsigned char>(b[2]) == 0xFF;
}

// libpng reports an error through png_error, which must not return: it jumps back to
// decode_png(), whose frame holds nothing that needs a destructor once the jump is set.
struct PngInput {
    std::string_view bytes;
    std::size_t at = 0;
    char message[200];
};

void png_from_memory(png_structp png, png_bytep out, png_size_t length) {
    auto* in = static_cast<PngInput*>(png_get_io_ptr(png));
    if (length > in->bytes.size() - in->at) png_error(png, "the data ends before the image does");
    std::memcpy(out, in->bytes.data() + in->at, length);
    in->at += length;
}
void png_fail(png_structp png, png_const_charp message) {
    auto* in = static_cast<PngInput*>(png_get_error_ptr(png));
    std::snprintf(in->message, sizeof in->message, "%s", message);
    png_longjmp(png, 1);
}
void png_ignore_warning(png_structp, png_const_charp) {}

// Decodes every row (CRCs and compressed data checked) into one row's buffer. Returns false
// with input.message set when libpng refuses the data.
bool decode_png(PngInput& input, std::vector<png_byte>& row, png_uint_32& width, png_uint_32& height) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &input, png_fail, png_ignore_warning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_set_read_fn(png, &input, png_from_memory);
    png_read_info(png, info);
    width = png_get_image_width(png, info);
    height = png_get_image_height(png, info);
    if (width > kMaxImageSide || height > kMaxImageSide) {  // refused by its size, undecoded
        png_destroy_read_struct(&png, &info, nullptr);
        return true;
    }
    const int passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);
    row.resize(png_get_rowbytes(png, info));
    for (int pass = 0; pass < passes; ++pass)
        for (png_uint_32 y = 0; y < height; ++y) png_read_row(png, row.data(), nullptr);
    png_read_end(png, nullptr);
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

ImageHeader read_png(std::string_view bytes) {
    // The last chunk of every PNG is an empty IEND (length 0, type, CRC): a cheap first test
    // that the upload arrived whole.
    static constexpr unsigned char kIend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    if (bytes.size() < 12 || std::memcmp(bytes.data() + bytes.size() - 12, kIend, 12) != 0)
        throw invalid_image("the PNG is truncated: it does not end with its IEND chunk");
    PngInput input{bytes, 0, {}};
    std::vector<png_byte> row;
    png_uint_32 width = 0, height = 0;
    if (!decode_png(input, row, width, height)) throw invalid_image(std::string("the PNG cannot be read: ") + input.message);
    return {"image/png", static_cast<std::int64_t>(width), static_cast<std::int64_t>(height)};
}

// libjpeg reports a fatal error through error_exit, which must not return: it jumps back
// to decode(), whose frame holds nothing that needs a destructor.
struct JpegError {
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
    bool ended_early;  // the data stopped before the image did: a cut-off upload
};

// Warnings (level -1) are libjpeg's "corrupt data" notes; the one that matters here is the
// end of the file coming before the image's end. Others (extraneous bytes between markers,
// which some cameras write) leave a decodable image and are let through.
void jpeg_note(j_common_ptr info, int level) {
    auto* err = reinterpret_cast<JpegError*>(info->err);
    if (level < 0 && info->err->msg_code == JWRN_JPEG_EOF) err->ended_early = true;
}

void jpeg_fail(j_common_ptr info) {
    auto* err = reinterpret_cast<JpegError*>(info->err);
    (*info->err->format_message)(info, err->message);
    std::longjmp(err->jump, 1);
}

// 0 on success (err.ended_early says whether the data was cut short); otherwise err.message
// says why.
int decode(const unsigned char* data, unsigned long size, JpegError& err, JDIMENSION& width,
           JDIMENSION& height, unsigned char* row, std::size_t row_bytes) {
    jpeg_decompress_struct info;
    info.err = jpeg_std_error(&err.mgr);
    err.mgr.error_exit = jpeg_fail;
    err.mgr.output_message = [](j_common_ptr) {};
    err.mgr.emit_message = jpeg_note;
    if (setjmp(err.jump)) {
        jpeg_destroy_decompress(&info);
        return 1;
    }
    jpeg_create_decompress(&info);
    // A progressive JPEG keeps every coefficient until its last scan: bounded, a huge one is
    // refused ("insufficient memory") rather than taking the server's memory.
    info.mem->max_memory_to_use = 256L * 1024 * 1024;
    jpeg_mem_src(&info, data, size);
    jpeg_read_header(&info, TRUE);
    width = info.image_width;
    height = info.image_height;
    if (width == 0 || height == 0 || width > kMaxImageSide || height > kMaxImageSide) {
        jpeg_destroy_decompress(&info);
        return 2;
    }
    // Its own colour space (grey, RGB or CMYK: libjpeg converts CMYK to nothing else) at 1/8
    // scale: every entropy-coded byte is still read, at a fraction of the work.
    info.scale_num = 1;
    info.scale_denom = 8;
    jpeg_start_decompress(&info);
    if (static_cast<std::size_t>(info.output_width) * static_cast<std::size_t>(info.output_components) > row_bytes) {
        jpeg_destroy_decompress(&info);
        return 3;
    }
    JSAMPROW rows[1] = {row};
    while (info.output_scanline < info.output_height) jpeg_read_scanlines(&info, rows, 1);
    jpeg_finish_decompress(&info);
    jpeg_destroy_decompress(&info);
    return 0;
}

ImageHeader read_jpeg(std::string_view bytes) {
    JpegError err{};
    JDIMENSION width = 0, height = 0;
    std::vector<unsigned char> row(static_cast<std::size_t>(kMaxImageSide / 8 + 8) * 4);  // up to 4 components
    const int rc = decode(reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()), err,
                          width, height, row.data(), row.size());
    if (rc == 1) throw invalid_image(std::string("the JPEG cannot be read: ") + err.message);
    if (rc == 0 && err.ended_early) throw invalid_image("the JPEG is truncated: its data ends before the image does");
    if (rc == 3) throw invalid_image("the JPEG cannot be read: unexpected output size");
    return {"image/jpeg", static_cast<std::int64_t>(width), static_cast<std::int64_t>(height)};
}

}  // namespace

std::string media_type(std::string_view content_type) {
    std::string t(content_type.substr(0, content_type.find(';')));
    t.erase(std::remove_if(t.begin(), t.end(), [](unsigned char c) { return c == ' ' || c == '\t'; }), t.end());
    std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return t;
}

void require_image_type(const std::string& type) {
    if (type != "image/png" && type != "image/jpeg")
        throw ApiError(415, "unsupported_media_type",
                       "a plan image is sent as its raw bytes with Content-Type image/png or image/jpeg" +
                           (type.empty() ? std::string(" (none was given)") : ", not " + type));
}

ImageHeader read_image_header(std::string_view bytes, const std::string& type) {
    require_image_type(type);
    if (bytes.empty()) throw invalid_image("the body is empty: send the image's bytes");
    const bool png = looks_like_png(bytes), jpeg = looks_like_jpeg(bytes);
    if (type == "image/png" && !png)
        throw invalid_image(jpeg ? "the body is a JPEG but Content-Type says image/png"
                                 : "the body is not a PNG (it does not start with the PNG signature)");
    if (type == "image/jpeg" && !jpeg)
        throw invalid_image(png ? "the body is a PNG but Content-Type says image/jpeg"
                                : "the body is not a JPEG (it does not start with a JPEG SOI marker)");
    // Decoding holds up to a row (PNG) or a 1/8-scale buffer (JPEG, ≤ 256 MiB) per upload:
    // two at a time bound what parallel uploads can take.
    static std::counting_semaphore<2> decoding(2);
    decoding.acquire();
    struct Release {
        ~Release() { decoding.release(); }
    } release;
    const ImageHeader h = png ? read_png(bytes) : read_jpeg(bytes);
    if (h.width_px <= 0 || h.height_px <= 0 || h.width_px > kMaxImageSide || h.height_px > kMaxImageSide)
        throw invalid_image("the image is " + std::to_string(h.width_px) + " × " + std::to_string(h.height_px) +
                            " pixels: each side must be 1 to " + std::to_string(kMaxImageSide));
    return h;
}

}  // namespace locus::http
