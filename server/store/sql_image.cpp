// A floor's plan image in SQLite (schema/006_floor_images.sql): one row per floor, the bytes
// a BLOB beside their metadata. No Change is published: no index or cache reads images.
#include "store/sql_store.hpp"

namespace locus::store {

namespace {
constexpr const char* kColumns =
    "floor_id, content_type, width_px, height_px, size_bytes, metres_per_pixel, origin_x, origin_y, rotation_deg, "
    "etag, updated_at";

FloorImage image_row(const Stmt& s) {
    FloorImage out;
    out.floor_id = s.int64(0);
    out.content_type = s.text(1);
    out.width_px = s.int64(2);
    out.height_px = s.int64(3);
    out.size_bytes = s.int64(4);
    out.placement = {s.real(5), s.real(6), s.real(7), s.real(8)};
    out.etag = s.text(9);
    out.updated_at = s.text(10);
    return out;
}
}  // namespace

std::optional<FloorImage> SqlStore::read_image(std::int64_t floor_id) {
    Stmt s(db_, std::string("SELECT ") + kColumns + " FROM floor_images WHERE floor_id = ?");
    s.bind(1, floor_id);
    if (!s.step()) return std::nullopt;
    return image_row(s);
}

std::optional<FloorImage> SqlStore::image_of_floor(std::int64_t floor_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);
    require_exists(kind("floors"), floor_id);
    auto out = read_image(floor_id);
    tx.commit();
    return out;
}

std::optional<std::pair<FloorImage, std::string>> SqlStore::image_with_bytes(std::int64_t floor_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);
    require_exists(kind("floors"), floor_id);
    Stmt s(db_, std::string("SELECT ") + kColumns + ", bytes FROM floor_images WHERE floor_id = ?");
    s.bind(1, floor_id);
    std::optional<std::pair<FloorImage, std::string>> out;
    if (s.step()) out.emplace(image_row(s), s.blob(11));
    tx.commit();
    return out;
}

std::pair<FloorImage, bool> SqlStore::put_image(const FloorImage& image, std::string_view bytes) {
    return write([&](std::vector<Change>&) {
        require_exists(kind("floors"), image.floor_id);
        const bool fresh = !read_image(image.floor_id);
        Stmt s(db_,
               "INSERT INTO floor_images (floor_id, content_type, bytes, size_bytes, width_px, height_px, metres_per_pixel, "
               "origin_x, origin_y, rotation_deg, etag) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
               "ON CONFLICT (floor_id) DO UPDATE SET content_type = excluded.content_type, bytes = excluded.bytes, "
               "size_bytes = excluded.size_bytes, width_px = excluded.width_px, height_px = excluded.height_px, "
               "metres_per_pixel = excluded.metres_per_pixel, origin_x = excluded.origin_x, origin_y = excluded.origin_y, "
               "rotation_deg = excluded.rotation_deg, etag = excluded.etag, "
               "updated_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now')");
        const auto& p = image.placement;
        s.bind(1, image.floor_id).bind(2, image.content_type).bind_blob(3, bytes).bind(4, static_cast<std::int64_t>(bytes.size()));
        s.bind(5, image.width_px).bind(6, image.height_px).bind(7, p.metres_per_pixel).bind(8, p.origin_x).bind(9, p.origin_y);
        s.bind(10, p.rotation_deg).bind(11, image.etag).run();
        return std::pair{*read_image(image.floor_id), fresh};
    });
}

FloorImage SqlStore::change_placement(std::int64_t floor_id, const PlacementChange& change) {
    return write([&](std::vector<Change>&) {
        require_exists(kind("floors"), floor_id);
        const auto image = read_image(floor_id);
        if (!image) throw NotFound("floor " + std::to_string(floor_id) + " has no image");
        const auto& p = image->placement;
        Stmt s(db_,
               "UPDATE floor_images SET metres_per_pixel = ?, origin_x = ?, origin_y = ?, rotation_deg = ?, "
               "updated_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now') WHERE floor_id = ?");
        s.bind(1, change.metres_per_pixel.value_or(p.metres_per_pixel)).bind(2, change.origin_x.value_or(p.origin_x));
        s.bind(3, change.origin_y.value_or(p.origin_y)).bind(4, change.rotation_deg.value_or(p.rotation_deg)).bind(5, floor_id).run();
        return *read_image(floor_id);
    });
}

void SqlStore::remove_image(std::int64_t floor_id) {
    write([&](std::vector<Change>&) {
        require_exists(kind("floors"), floor_id);
        Stmt s(db_, "DELETE FROM floor_images WHERE floor_id = ?");
        s.bind(1, floor_id).run();
        if (db_.changes() == 0) throw NotFound("floor " + std::to_string(floor_id) + " has no image");
    });
}

}  // namespace locus::store
