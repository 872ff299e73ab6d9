// A floor's plan image: PUT, GET and DELETE /v1/floors/{id}/image (the raw PNG or JPEG), and
// GET/PATCH /v1/floors/{id}/image/placement (its size and where it lies on the floor, as JSON;
// a PATCH moves, scales or turns it without sending the image again).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "http/app.hpp"
#include "http/plans/image_header.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

// Coordinates as a plan's (plan.hpp): far beyond any building, small enough to stay exact.
constexpr double kMaxOrigin = 1e5;
constexpr double kMaxMetresPerPixel = 1000;

// A query parameter that must be a finite number in [lo, hi] (and > 0 when `positive`).
std::optional<double> query_number(const httplib::Request& req, const char* name, double lo, double hi, bool positive) {
    if (!req.has_param(name)) return std::nullopt;
    const std::string text = req.get_param_value(name);
    double v = 0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    const bool ok = !text.empty() && ec == std::errc() && ptr == text.data() + text.size() && std::isfinite(v) && v >= lo &&
                    v <= hi && (!positive || v > 0);
    if (!ok) {
        char bounds[96];
        if (positive) std::snprintf(bounds, sizeof bounds, "a number > 0 and <= %g", hi);
        else std::snprintf(bounds, sizeof bounds, "a number in [%g, %g]", lo, hi);
        throw ApiError(400, "invalid_query", std::string("'") + name + "' must be " + bounds + ", not '" + text.substr(0, 40) + "'");
    }
    return v;
}

store::ImagePlacement parse_placement(const httplib::Request& req) {
    for (const auto& [key, value] : req.params)
        if (key != "metres_per_pixel" && key != "origin_x" && key != "origin_y" && key != "rotation_deg")
            throw ApiError(400, "invalid_query",
                           "unknown query parameter '" + key.substr(0, 40) +
                               "' (a plan image takes metres_per_pixel, origin_x, origin_y, rotation_deg)");
    store::ImagePlacement p;
    const auto m = query_number(req, "metres_per_pixel", 0, kMaxMetresPerPixel, true);
    if (!m)
        throw ApiError(400, "invalid_query",
                       "missing query parameter 'metres_per_pixel' (the image's scale: floor metres per pixel, > 0)");
    p.metres_per_pixel = *m;
    p.origin_x = query_number(req, "origin_x", -kMaxOrigin, kMaxOrigin, false).value_or(0);
    p.origin_y = query_number(req, "origin_y", -kMaxOrigin, kMaxOrigin, false).value_or(0);
    p.rotation_deg = query_number(req, "rotation_deg", -360, 360, false).value_or(0);
    return p;
}

// The body of PATCH …/image/placement: any of the four placement members, bounded as the
// PUT's query parameters are.
store::PlacementChange parse_placement_change(const std::string& body) {
    const json j = parse_object(body);
    only_fields(j, {"metres_per_pixel", "origin_x", "origin_y", "rotation_deg"}, "");
    store::PlacementChange c;
    const auto member = [&](const char* name, double lo, double hi) -> std::optional<double> {
        if (!j.contains(name)) return std::nullopt;
        return finite_number(j, name, "", lo, hi);
    };
    c.metres_per_pixel = member("metres_per_pixel", 0, kMaxMetresPerPixel);
    if (c.metres_per_pixel && *c.metres_per_pixel <= 0) throw invalid_field("'metres_per_pixel' must be > 0");
    c.origin_x = member("origin_x", -kMaxOrigin, kMaxOrigin);
    c.origin_y = member("origin_y", -kMaxOrigin, kMaxOrigin);
    c.rotation_deg = member("rotation_deg", -360, 360);
    return c;
}

// A strong tag of the bytes (FNV-1a, 64 bits, and the length): equal bytes, equal tag, so a
// client's cached copy stays valid across a PUT of the same file.
std::string content_tag(std::string_view bytes) {
    std::uint64_t h = 1469598103934665603ULL;
    for (const unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ULL;
    }
    char buf[48];
    std::snprintf(buf, sizeof buf, "\"%016llx-%llx\"", static_cast<unsigned long long>(h),
                  static_cast<unsigned long long>(bytes.size()));
    return buf;
}

// Where pixel (u, v) (u right, v down from the top-left corner) lands on the floor.
json floor_point(const store::FloorImage& img, double u, double v) {
    const auto& p = img.placement;
    const double t = p.rotation_deg * std::numbers::pi / 180.0;
    const double a = p.metres_per_pixel * u, b = p.metres_per_pixel * (static_cast<double>(img.height_px) - v);
    return json::array({p.origin_x + a * std::cos(t) - b * std::sin(t), p.origin_y + a * std::sin(t) + b * std::cos(t)});
}

json image_json(const store::FloorImage& img) {
    const auto w = static_cast<double>(img.width_px), h = static_cast<double>(img.height_px);
    return {{"floor_id", img.floor_id},
            {"content_type", img.content_type},
            {"width_px", img.width_px},
            {"height_px", img.height_px},
            {"size_bytes", img.size_bytes},
            {"metres_per_pixel", img.placement.metres_per_pixel},
            {"origin_x", img.placement.origin_x},
            {"origin_y", img.placement.origin_y},
            {"rotation_deg", img.placement.rotation_deg},
            // The image's corners on the floor, counter-clockwise from its bottom-left.
            {"corners", json::array({floor_point(img, 0, h), floor_point(img, w, h), floor_point(img, w, 0), floor_point(img, 0, 0)})},
            {"etag", img.etag},
            {"updated_at", img.updated_at}};
}

// If-None-Match lists the tag (weakly compared: W/"x" matches "x"), or is "*".
bool client_has(const httplib::Request& req, const std::string& etag) {
    if (!req.has_header("If-None-Match")) return false;
    const std::string list = req.get_header_value("If-None-Match");
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t end = std::min(list.find(',', start), list.size());
        std::string tag = list.substr(start, end - start);
        tag.erase(0, tag.find_first_not_of(" \t"));
        tag.erase(tag.find_last_not_of(" \t") + 1);
        if (tag.starts_with("W/")) tag.erase(0, 2);
        if (tag == "*" || tag == etag) return true;
        start = end + 1;
    }
    return false;
}

[[noreturn]] void no_image(std::int64_t floor_id) {
    throw ApiError(404, "not_found", "floor " + std::to_string(floor_id) + " has no image");
}

}  // namespace

void App::install_image_routes() {
    const std::string path = R"(/v1/floors/(\d+)/image)";
    // An image may be larger than any JSON body: this route alone takes up to 20 MiB.
    server_.allow_body("PUT", path, kMaxImageBytes, false);  // a PNG or JPEG is compressed already

    server_.Put(path, [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            if (req.body.size() > kMaxImageBytes) {  // a chunked body, counted once read
                const auto r = body_too_large(kMaxImageBytes);
                throw ApiError(r.status, r.code, r.message);
            }
            // Cheap checks first: the type, the placement, then the bytes; the floor last, as
            // every write looks its path's ids up after its body (a bad upload to an unknown
            // floor is 4xx for the upload).
            const auto type = media_type(req.get_header_value("Content-Type"));
            require_image_type(type);
            const auto placement = parse_placement(req);
            const auto header = read_image_header(req.body, type);
            store::FloorImage image;
            image.floor_id = floor_id;
            image.content_type = header.content_type;
            image.width_px = header.width_px;
            image.height_px = header.height_px;
            image.placement = placement;
            image.etag = content_tag(req.body);
            const auto [stored, created] = store_.put_image(image, req.body);
            if (created) res.set_header("Location", "/v1/floors/" + std::to_string(floor_id) + "/image");
            return std::pair{created ? 201 : 200, image_json(stored)};
        });
    });
    server_.Get(path, [this](const httplib::Request& req, httplib::Response& res) {
        guarded(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            // A client that has the image is answered from the metadata alone: the bytes (up
            // to 20 MiB, read under the store's lock) are read only to be sent.
            if (const auto image = store_.image_of_floor(floor_id); image && client_has(req, image->etag)) {
                res.set_header("ETag", image->etag);
                res.set_header("Cache-Control", "no-cache");
                res.status = 304;
                return;
            }
            auto found = store_.image_with_bytes(floor_id);
            if (!found) no_image(floor_id);
            auto& [image, bytes] = *found;
            res.set_header("ETag", image.etag);
            res.set_header("Cache-Control", "no-cache");  // may be kept, but asked again each time (304 when unchanged)
            if (client_has(req, image.etag)) {  // replaced by the same bytes in between
                res.status = 304;
                return;
            }
            res.status = 200;
            res.set_content(std::move(bytes), image.content_type);
        });
    });
    server_.Get(path + "/placement", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const auto image = store_.image_of_floor(floor_id);
            if (!image) no_image(floor_id);
            return std::pair{200, image_json(*image)};
        });
    });
    server_.Patch(path + "/placement", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            return std::pair{200, image_json(store_.change_placement(floor_id, parse_placement_change(req.body)))};
        });
    });
    server_.Delete(path, [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            store_.remove_image(parse_id(req.matches[1].str(), "floor"));
            return std::pair{204, json()};
        });
    });
}

}  // namespace locus::http
