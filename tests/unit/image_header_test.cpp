// read_image_header: what an uploaded plan image is, read with libpng and libjpeg. Images
// are written here with the same libraries, in the colour spaces a drawing comes in.
#include <gtest/gtest.h>

#include <vector>

#include "http/api_error.hpp"
#include "http/plans/image_header.hpp"
#include "images/test_images.hpp"

namespace image_header_test {
namespace {

using locus::http::ApiError;
using locus::http::read_image_header;

std::string png(unsigned w, unsigned h, png_uint_32 format) {
    png_image image{};
    image.width = w;
    image.height = h;
    image.format = format;
    return locus::testing::png_bytes(w, h, format, std::vector<std::uint8_t>(PNG_IMAGE_SIZE(image), 90));
}

std::string jpeg(unsigned w, unsigned h, J_COLOR_SPACE space, int components, bool progressive = false) {
    return locus::testing::jpeg_bytes(w, h, locus::testing::image_pattern(w, h, components),
                                      {.space = space, .components = components, .progressive = progressive});
}

// The ApiError read_image_header throws, as "status code: message".
std::string refusal(const std::string& bytes, const std::string& type) {
    try {
        read_image_header(bytes, type);
    } catch (const ApiError& e) {
        return std::to_string(e.status) + " " + e.code + ": " + e.what();
    }
    return "accepted";
}

TEST(ImageHeader, PngsOfEveryFormatGiveTheirSize) {
    for (const png_uint_32 format : {png_uint_32{PNG_FORMAT_GRAY}, png_uint_32{PNG_FORMAT_RGB}, png_uint_32{PNG_FORMAT_RGBA}, png_uint_32{PNG_FORMAT_GA}}) {
        const auto h = read_image_header(png(37, 11, format), "image/png");
        EXPECT_EQ(h.content_type, "image/png");
        EXPECT_EQ(h.width_px, 37);
        EXPECT_EQ(h.height_px, 11);
    }
}

TEST(ImageHeader, JpegsOfEveryColourSpaceGiveTheirSize) {
    struct Case {
        J_COLOR_SPACE space;
        int components;
        bool progressive;
    };
    for (const auto& c : {Case{JCS_GRAYSCALE, 1, false}, Case{JCS_RGB, 3, false}, Case{JCS_CMYK, 4, false}, Case{JCS_RGB, 3, true}}) {
        const auto h = read_image_header(jpeg(301, 97, c.space, c.components, c.progressive), "image/jpeg");
        EXPECT_EQ(h.width_px, 301) << c.space;
        EXPECT_EQ(h.height_px, 97) << c.space;
    }
}

TEST(ImageHeader, ACutOffJpegIsRefusedButStrayBytesBetweenMarkersAreNot) {
    const auto whole = jpeg(400, 300, JCS_RGB, 3);
    EXPECT_EQ(refusal(whole.substr(0, whole.size() * 2 / 3), "image/jpeg"),
              "422 invalid_image: the JPEG is truncated: its data ends before the image does");
    // Bytes before the end marker (some cameras write them): libjpeg warns and decodes it all.
    std::string stray = whole.substr(0, whole.size() - 2) + "xyz" + whole.substr(whole.size() - 2);
    EXPECT_EQ(refusal(stray, "image/jpeg"), "accepted");
    EXPECT_EQ(refusal(whole.substr(0, 100), "image/jpeg").substr(0, 43), "422 invalid_image: the JPEG cannot be read:");
}

TEST(ImageHeader, TheTypeTheBytesAndTheSizeMustAgree) {
    const auto p = png(4, 4, PNG_FORMAT_GRAY);
    const auto j = jpeg(4, 4, JCS_GRAYSCALE, 1);
    EXPECT_EQ(refusal(p, "image/gif").substr(0, 27), "415 unsupported_media_type:");
    EXPECT_EQ(refusal(p, "").find("(none was given)") != std::string::npos, true);
    EXPECT_EQ(refusal(p, "image/jpeg"), "422 invalid_image: the body is a PNG but Content-Type says image/jpeg");
    EXPECT_EQ(refusal(j, "image/png"), "422 invalid_image: the body is a JPEG but Content-Type says image/png");
    EXPECT_EQ(refusal(p + "junk", "image/png"), "422 invalid_image: the PNG is truncated: it does not end with its IEND chunk");
    EXPECT_EQ(refusal(png(20000, 1, PNG_FORMAT_GRAY), "image/png"), "accepted");
    EXPECT_EQ(refusal(png(20001, 1, PNG_FORMAT_GRAY), "image/png"),
              "422 invalid_image: the image is 20001 × 1 pixels: each side must be 1 to 20000");
    EXPECT_EQ(refusal(jpeg(1, 20001, JCS_GRAYSCALE, 1), "image/jpeg"),
              "422 invalid_image: the image is 1 × 20001 pixels: each side must be 1 to 20000");
}

TEST(ImageHeader, APngWhoseImageDataIsDamagedIsRefusedThoughItEndsWell) {
    const auto whole = locus::testing::png_bytes(300, 200, PNG_FORMAT_RGB, locus::testing::image_pattern(300, 200, 3));
    const auto idat = whole.find("IDAT");
    ASSERT_NE(idat, std::string::npos);
    std::string damaged = whole;
    damaged[idat + 4 + 100] = static_cast<char>(damaged[idat + 4 + 100] ^ 0x5A);  // compressed data; its CRC no longer holds
    EXPECT_EQ(refusal(damaged, "image/png").substr(0, 42), "422 invalid_image: the PNG cannot be read:");
    EXPECT_EQ(refusal(whole, "image/png"), "accepted");
}

TEST(ImageHeader, MediaTypesAreComparedWithoutParametersOrCase) {
    EXPECT_EQ(locus::http::media_type("Image/PNG; charset=binary"), "image/png");
    EXPECT_EQ(locus::http::media_type(" image/jpeg "), "image/jpeg");
    EXPECT_EQ(locus::http::media_type(""), "");
}

}  // namespace
}  // namespace image_header_test
