// A floor's plan image against the real server: PNG and JPEG bytes come back identical with
// their type and tag, the placement round-trips and places the corners as documented, a
// replace and a delete, the image survives a restart and goes with its floor; every bad
// upload is refused naming the problem, with nothing written.
#include <gtest/gtest.h>
#include <httplib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "hierarchy.hpp"
#include "images/test_images.hpp"
#include "server_process.hpp"

namespace server_plan_image_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

// A w × h grey PNG with a diagonal, written by libpng.
std::string make_png(unsigned w, unsigned h) {
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w) * h, 200);
    for (unsigned i = 0; i < std::min(w, h); ++i) pixels[static_cast<std::size_t>(i) * w + i] = 0;
    return locus::testing::png_bytes(w, h, PNG_FORMAT_GRAY, pixels);
}

// A w × h grey JPEG, written by libjpeg.
std::string make_jpeg(unsigned w, unsigned h) {
    return locus::testing::jpeg_bytes(w, h, locus::testing::image_pattern(w, h, 1));
}

struct Raw {
    int status = 0;
    std::string body, content_type, etag;
    json error_code() const {
        const auto j = json::parse(body, nullptr, false);
        return j.is_object() ? j.value("/error/code"_json_pointer, json()) : json();
    }
};

Raw to_raw(const httplib::Result& r) {
    Raw out;
    if (!r) return out;
    out.status = r->status;
    out.body = r->body;
    out.content_type = r->get_header_value("Content-Type");
    out.etag = r->get_header_value("ETag");
    return out;
}

struct PlanImage : ::testing::Test {
    ServerProcess s;
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    std::string image = "/v1/floors/" + std::to_string(h.floor) + "/image";
    std::string api_key;

    httplib::Client client() const {
        httplib::Client c("127.0.0.1", s.port());
        c.set_read_timeout(30, 0);
        c.set_write_timeout(30, 0);
        return c;
    }
    httplib::Headers auth() const {
        if (api_key.empty()) return {};
        return {{"Authorization", "Bearer " + api_key}};
    }
    Raw put(const std::string& bytes, const std::string& type, const std::string& query = "?metres_per_pixel=0.05",
            const std::string& path = "") const {
        auto c = client();
        return to_raw(c.Put((path.empty() ? image : path) + query, auth(), bytes, type));
    }
    Raw get(const std::string& path, httplib::Headers headers = {}) const {
        auto c = client();
        return to_raw(c.Get(path, headers));
    }
};

TEST_F(PlanImage, APngReadsBackIdenticalWithItsPlacement) {
    EXPECT_EQ(get(image).status, 404);
    EXPECT_EQ(get(image + "/placement").status, 404);
    const auto png = make_png(40, 20);
    const auto put1 = put(png, "image/png", "?metres_per_pixel=0.25&origin_x=3&origin_y=-2&rotation_deg=90");
    ASSERT_EQ(put1.status, 201) << put1.body;
    const auto meta = json::parse(put1.body);
    EXPECT_EQ(meta.at("content_type"), "image/png");
    EXPECT_EQ(meta.at("width_px"), 40);
    EXPECT_EQ(meta.at("height_px"), 20);
    EXPECT_EQ(meta.at("size_bytes"), png.size());
    EXPECT_EQ(meta.at("metres_per_pixel"), 0.25);
    EXPECT_EQ(meta.at("origin_x"), 3.0);
    EXPECT_EQ(meta.at("origin_y"), -2.0);
    EXPECT_EQ(meta.at("rotation_deg"), 90.0);
    // 40 × 20 px at 0.25 m: 10 m × 5 m; its bottom-left at (3, -2), turned 90° counter-
    // clockwise, so its bottom edge runs up the y axis and its top edge lies 5 m to the west.
    const std::vector<std::pair<double, double>> corners = {{3, -2}, {3, 8}, {-2, 8}, {-2, -2}};
    ASSERT_EQ(meta.at("corners").size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(meta.at("corners")[i][0].get<double>(), corners[i].first, 1e-9) << i;
        EXPECT_NEAR(meta.at("corners")[i][1].get<double>(), corners[i].second, 1e-9) << i;
    }

    const auto got = get(image);
    ASSERT_EQ(got.status, 200);
    EXPECT_EQ(got.body, png);
    EXPECT_EQ(got.content_type, "image/png");
    EXPECT_EQ(got.etag, meta.at("etag").get<std::string>());
    EXPECT_EQ(json::parse(get(image + "/placement").body), meta);
    // A client holding this copy is told it is current.
    EXPECT_EQ(get(image, {{"If-None-Match", got.etag}}).status, 304);
    EXPECT_EQ(get(image, {{"If-None-Match", "\"other\""}}).status, 200);

    // It survives a restart (it is in the database file).
    s.stop();
    s.start();
    EXPECT_EQ(get(image).body, png);
    EXPECT_EQ(json::parse(get(image + "/placement").body), meta);
}

TEST_F(PlanImage, DefaultsPutTheBottomLeftCornerOnTheFloorsOrigin) {
    const auto r = put(make_png(10, 30), "image/png", "?metres_per_pixel=0.5");
    ASSERT_EQ(r.status, 201) << r.body;
    const auto meta = json::parse(r.body);
    EXPECT_EQ(meta.at("origin_x"), 0.0);
    EXPECT_EQ(meta.at("rotation_deg"), 0.0);
    EXPECT_EQ(meta.at("corners"), json::parse("[[0.0,0.0],[5.0,0.0],[5.0,15.0],[0.0,15.0]]"));
}

TEST_F(PlanImage, AJpegReplacesThePngAndDeleteRemovesIt) {
    const auto png = make_png(8, 8);
    ASSERT_EQ(put(png, "image/png").status, 201);
    const auto first_tag = get(image).etag;
    const auto jpeg = make_jpeg(64, 48);
    const auto r = put(jpeg, "image/jpeg; charset=binary", "?metres_per_pixel=0.1");
    ASSERT_EQ(r.status, 200) << r.body;  // replaced
    const auto meta = json::parse(r.body);
    EXPECT_EQ(meta.at("content_type"), "image/jpeg");
    EXPECT_EQ(meta.at("width_px"), 64);
    EXPECT_EQ(meta.at("height_px"), 48);
    const auto got = get(image);
    EXPECT_EQ(got.body, jpeg);
    EXPECT_EQ(got.content_type, "image/jpeg");
    EXPECT_NE(got.etag, first_tag);
    EXPECT_EQ(get(image, {{"If-None-Match", first_tag}}).status, 200);  // the old copy is stale

    auto c = client();
    EXPECT_EQ(to_raw(c.Delete(image)).status, 204);
    const auto gone = get(image);
    EXPECT_EQ(gone.status, 404);
    EXPECT_NE(gone.body.find("floor " + std::to_string(h.floor) + " has no image"), std::string::npos) << gone.body;
    EXPECT_EQ(to_raw(c.Delete(image)).status, 404);
}

TEST_F(PlanImage, DeletingTheFloorDeletesItsImage) {
    ASSERT_EQ(put(make_png(4, 4), "image/png").status, 201);
    auto c = client();
    ASSERT_EQ(to_raw(c.Delete("/v1/floors/" + std::to_string(h.floor))).status, 204);
    const auto r = get(image);
    EXPECT_EQ(r.status, 404);
    EXPECT_NE(r.body.find("floor " + std::to_string(h.floor) + " not found"), std::string::npos) << r.body;
}

TEST_F(PlanImage, BadUploadsAreRefusedNamingTheProblemAndWriteNothing) {
    const auto png = make_png(16, 16);
    const auto jpeg = make_jpeg(16, 16);
    ASSERT_EQ(put(png, "image/png", "?metres_per_pixel=0.5").status, 201);
    const auto before = get(image + "/placement").body;

    std::string truncated_png = png.substr(0, png.size() - 20);
    std::string corrupt_header = png;
    corrupt_header[20] = static_cast<char>(corrupt_header[20] ^ 0x40);  // inside IHDR: its CRC no longer holds
    const auto big_jpeg = make_jpeg(256, 256);  // cut inside its image data, past the headers
    std::string truncated_jpeg = big_jpeg.substr(0, big_jpeg.size() * 3 / 4);
    struct Case {
        std::string bytes, type, query;
        int status;
        const char* code;
        const char* message;
    };
    const std::string q = "?metres_per_pixel=0.05";
    const std::vector<Case> cases = {
        {png, "image/gif", q, 415, "unsupported_media_type", "image/png or image/jpeg, not image/gif"},
        {png, "application/json", q, 415, "unsupported_media_type", "not application/json"},
        {png, "image/jpeg", q, 422, "invalid_image", "the body is a PNG but Content-Type says image/jpeg"},
        {jpeg, "image/png", q, 422, "invalid_image", "the body is a JPEG but Content-Type says image/png"},
        {"hello", "image/png", q, 422, "invalid_image", "not a PNG"},
        {"", "image/png", q, 422, "invalid_image", "the body is empty"},
        {truncated_png, "image/png", q, 422, "invalid_image", "the PNG is truncated"},
        {corrupt_header, "image/png", q, 422, "invalid_image", "the PNG cannot be read"},
        {png.substr(0, 30), "image/png", q, 422, "invalid_image", "the PNG is truncated"},
        {truncated_jpeg, "image/jpeg", q, 422, "invalid_image", "the JPEG is truncated"},
        {jpeg.substr(0, 40), "image/jpeg", q, 422, "invalid_image", "the JPEG"},
        {make_png(20001, 1), "image/png", q, 422, "invalid_image", "20001 × 1 pixels: each side must be 1 to 20000"},
        {png, "image/png", "", 400, "invalid_query", "missing query parameter 'metres_per_pixel'"},
        {png, "image/png", "?metres_per_pixel=0", 400, "invalid_query", "'metres_per_pixel' must be a number > 0"},
        {png, "image/png", "?metres_per_pixel=-1", 400, "invalid_query", "'metres_per_pixel' must be"},
        {png, "image/png", "?metres_per_pixel=nan", 400, "invalid_query", "'metres_per_pixel' must be"},
        {png, "image/png", "?metres_per_pixel=inf", 400, "invalid_query", "'metres_per_pixel' must be"},
        {png, "image/png", "?metres_per_pixel=abc", 400, "invalid_query", "'metres_per_pixel' must be"},
        {png, "image/png", "?metres_per_pixel=1&origin_x=1e9", 400, "invalid_query", "'origin_x' must be a number in"},
        {png, "image/png", "?metres_per_pixel=1&rotation_deg=400", 400, "invalid_query", "'rotation_deg'"},
        {png, "image/png", "?metres_per_pixel=1&scale=2", 400, "invalid_query", "unknown query parameter 'scale'"},
    };
    for (const auto& c : cases) {
        const auto r = put(c.bytes, c.type, c.query);
        EXPECT_EQ(r.status, c.status) << c.message << ": " << r.body;
        EXPECT_EQ(r.error_code(), c.code) << r.body;
        EXPECT_NE(r.body.find(c.message), std::string::npos) << c.message << " not in " << r.body;
        EXPECT_EQ(get(image + "/placement").body, before) << c.message;
    }
    EXPECT_EQ(get(image).body, png);

    // An unknown floor, and one that is not a number.
    const auto unknown = put(png, "image/png", q, "/v1/floors/987654/image");
    EXPECT_EQ(unknown.status, 404);
    EXPECT_NE(unknown.body.find("floor 987654 not found"), std::string::npos) << unknown.body;
    EXPECT_EQ(get("/v1/floors/987654/image/placement").status, 404);
}

TEST_F(PlanImage, MoreThan20MiBIsRefusedOnThisRouteOnly) {
    std::string big = make_png(4, 4);
    big.resize(20u * 1024 * 1024 + 1, '\0');
    const auto r = put(big, "image/png");
    EXPECT_EQ(r.status, 413) << r.body;
    EXPECT_EQ(r.error_code(), "payload_too_large");
    EXPECT_NE(r.body.find("20971520 bytes"), std::string::npos) << r.body;
    EXPECT_EQ(get(image).status, 404);

    // 9 MiB passes the route's limit (the image itself is then refused for its content)…
    std::string nine = make_png(4, 4);
    nine.resize(9u * 1024 * 1024, '\0');
    EXPECT_EQ(put(nine, "image/png").status, 422);
    // …while JSON routes keep the server's 8 MiB.
    auto c = client();
    const auto json_body = to_raw(c.Put("/v1/floors/" + std::to_string(h.floor) + "/plan", std::string(9u * 1024 * 1024, ' '),
                                        "application/json"));
    EXPECT_EQ(json_body.status, 413) << json_body.body;
}

TEST(PlanImageAuth, WritesNeedTheApiKey) {
    ServerProcess locked({"--api-key", "s3cret"});
    locked.set_api_key("s3cret");
    const auto hh = locus::testing::make_hierarchy(locked);
    httplib::Client c("127.0.0.1", locked.port());
    const std::string path = "/v1/floors/" + std::to_string(hh.floor) + "/image";
    const auto png = make_png(4, 4);
    const auto no_key = to_raw(c.Put(path + "?metres_per_pixel=0.1", png, "image/png"));
    EXPECT_EQ(no_key.status, 401);
    EXPECT_EQ(no_key.error_code(), "unauthorized");
    const httplib::Headers wrong = {{"Authorization", "Bearer nope"}}, right = {{"Authorization", "Bearer s3cret"}};
    EXPECT_EQ(to_raw(c.Put(path + "?metres_per_pixel=0.1", wrong, png, "image/png")).status, 401);
    EXPECT_EQ(to_raw(c.Get(path)).status, 404);  // nothing was written
    EXPECT_EQ(to_raw(c.Put(path + "?metres_per_pixel=0.1", right, png, "image/png")).status, 201);
    EXPECT_EQ(to_raw(c.Get(path)).body, png);  // reads need no key
    EXPECT_EQ(to_raw(c.Patch(path + "/placement", R"({"origin_x": 1})", "application/json")).status, 401);
    EXPECT_EQ(to_raw(c.Patch(path + "/placement", right, R"({"origin_x": 1})", "application/json")).status, 200);
    EXPECT_EQ(to_raw(c.Delete(path)).status, 401);
    EXPECT_EQ(to_raw(c.Delete(path, right)).status, 204);
}

TEST_F(PlanImage, APatchMovesScalesOrTurnsTheImageWithoutSendingItAgain) {
    const auto png = make_png(40, 20);
    const auto put1 = put(png, "image/png", "?metres_per_pixel=0.25&origin_x=3&origin_y=-2");
    ASSERT_EQ(put1.status, 201) << put1.body;
    const std::string placement = image + "/placement";
    auto patch = [&](const std::string& body) {
        auto c = client();
        return to_raw(c.Patch(placement, body, "application/json"));
    };
    // Only the members given change: turned 90° about its bottom-left corner, still at (3, -2).
    const auto turned = patch(R"({"rotation_deg": 90})");
    ASSERT_EQ(turned.status, 200) << turned.body;
    const auto meta = json::parse(turned.body);
    EXPECT_EQ(meta.at("metres_per_pixel"), 0.25);
    EXPECT_EQ(meta.at("origin_x"), 3.0);
    EXPECT_EQ(meta.at("rotation_deg"), 90.0);
    EXPECT_NEAR(meta.at("corners")[2][0].get<double>(), -2.0, 1e-9);
    EXPECT_NEAR(meta.at("corners")[2][1].get<double>(), 8.0, 1e-9);
    EXPECT_EQ(json::parse(get(placement).body), meta);
    // The bytes and their tag are the upload's.
    EXPECT_EQ(get(image).body, png);
    EXPECT_EQ(meta.at("etag"), json::parse(put1.body).at("etag"));

    const auto before = get(placement).body;
    struct Case {
        std::string body;
        int status;
        const char* code;
        const char* message;
    };
    const std::vector<Case> bad = {
        {R"({"metres_per_pixel": 0})", 422, "invalid_field", "'metres_per_pixel' must be > 0"},
        {R"({"metres_per_pixel": -1})", 422, "out_of_range", "metres_per_pixel"},
        {R"({"origin_x": "3"})", 422, "invalid_field", "origin_x"},
        {R"({"origin_y": 1e9})", 422, "out_of_range", "origin_y"},
        {R"({"rotation_deg": 400})", 422, "out_of_range", "rotation_deg"},
        {R"({"scale": 2})", 422, "invalid_field", "unknown field 'scale'"},
        {R"([1, 2])", 400, "invalid_json", ""},
        {R"({"origin_x": )", 400, "invalid_json", ""},
    };
    for (const auto& c : bad) {
        const auto r = patch(c.body);
        EXPECT_EQ(r.status, c.status) << c.body << ": " << r.body;
        EXPECT_EQ(r.error_code(), c.code) << c.body << ": " << r.body;
        EXPECT_NE(r.body.find(c.message), std::string::npos) << c.message << " not in " << r.body;
        EXPECT_EQ(get(placement).body, before) << c.body;
    }
    // No image, no floor.
    ASSERT_EQ(to_raw(client().Delete(image)).status, 204);
    EXPECT_EQ(patch(R"({"origin_x": 1})").status, 404);
    auto c = client();
    EXPECT_EQ(to_raw(c.Patch("/v1/floors/987654/image/placement", R"({"origin_x": 1})", "application/json")).error_code(),
              "not_found");
}

}  // namespace
}  // namespace server_plan_image_test
