// The CLI's drawing reader (tools/image_file.hpp): PNG (grey, colour, with transparency over
// white) and JPEG files read into the same grey pixels, told apart by their bytes rather than
// their names; anything else refused naming the file.
#include <gtest/gtest.h>
#include <jpeglib.h>
#include <png.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "image_file.hpp"
#include "images/test_images.hpp"
#include "temp_dir.hpp"

namespace image_file_test {
namespace {

using locus::testing::TempDir;

constexpr int kW = 40, kH = 20;

// Black left half, white right half.
std::vector<std::uint8_t> half_black(int channels) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(kW * kH * channels), 255);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW / 2; ++x)
            for (int c = 0; c < channels; ++c) px[static_cast<std::size_t>((y * kW + x) * channels + c)] = 0;
    return px;
}

void write_file(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

void write_png(const std::string& path, png_uint_32 format, const std::vector<std::uint8_t>& px) {
    write_file(path, locus::testing::png_bytes(kW, kH, format, px));
}

void write_jpeg(const std::string& path, const std::vector<std::uint8_t>& rgb) {
    write_file(path, locus::testing::jpeg_bytes(kW, kH, rgb, {.space = JCS_RGB, .components = 3, .quality = 95}));
}

void expect_half_black(const locus::imaging::GreyImage& g, int tolerance) {
    ASSERT_EQ(g.width, kW);
    ASSERT_EQ(g.height, kH);
    ASSERT_EQ(g.pixels.size(), static_cast<std::size_t>(kW * kH));
    for (int y = 0; y < kH; ++y) {
        EXPECT_NEAR(g.pixels[static_cast<std::size_t>(y * kW + 2)], 0, tolerance);
        EXPECT_NEAR(g.pixels[static_cast<std::size_t>(y * kW + kW - 3)], 255, tolerance);
    }
}

TEST(ImageFile, PngInGreyOrColourReadsAsGrey) {
    TempDir t{"image"};
    write_png(t.file("grey.png"), PNG_FORMAT_GRAY, half_black(1));
    expect_half_black(locus::tools::read_grey_image(t.file("grey.png")), 0);
    write_png(t.file("rgb.png"), PNG_FORMAT_RGB, half_black(3));
    expect_half_black(locus::tools::read_grey_image(t.file("rgb.png")), 0);
}

TEST(ImageFile, TransparencyIsLaidOverWhite) {
    TempDir t{"image"};
    auto px = half_black(4);
    for (int y = 0; y < kH; ++y)  // the left half opaque black, the right half black but fully transparent
        for (int x = 0; x < kW; ++x) {
            auto* p = &px[static_cast<std::size_t>((y * kW + x) * 4)];
            p[0] = p[1] = p[2] = 0;
            p[3] = x < kW / 2 ? 255 : 0;
        }
    write_png(t.file("alpha.png"), PNG_FORMAT_RGBA, px);
    expect_half_black(locus::tools::read_grey_image(t.file("alpha.png")), 0);
}

TEST(ImageFile, JpegIsReadByItsBytesWhateverItsName) {
    TempDir t{"image"};
    write_jpeg(t.file("drawing.png"), half_black(3));  // misnamed on purpose
    expect_half_black(locus::tools::read_grey_image(t.file("drawing.png")), 12);
}

TEST(ImageFile, AnythingElseIsRefusedNamingTheFile) {
    TempDir t{"image"};
    std::ofstream(t.file("notes.png")) << "not an image";
    try {
        locus::tools::read_grey_image(t.file("notes.png"));
        ADD_FAILURE() << "accepted";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("notes.png' is neither a PNG nor a JPEG"), std::string::npos) << e.what();
    }
    // A PNG cut short after its header.
    write_png(t.file("whole.png"), PNG_FORMAT_GRAY, half_black(1));
    std::ifstream in(t.file("whole.png"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(t.file("cut.png"), std::ios::binary) << bytes.substr(0, 40);
    try {
        locus::tools::read_grey_image(t.file("cut.png"));
        ADD_FAILURE() << "accepted";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("cut.png' is not a readable PNG"), std::string::npos) << e.what();
    }
    EXPECT_THROW(locus::tools::read_grey_image(t.file("missing.png")), std::exception);
}

}  // namespace
}  // namespace image_file_test
