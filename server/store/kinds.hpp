#pragma once
// The resource kinds of the hierarchy, described once: the store builds its SQL from these
// and the HTTP layer validates request bodies against them.
#include <optional>
#include <string_view>
#include <vector>

namespace locus::store {

// Bound of every coordinate and size, in metres: UTM eastings and northings fit comfortably.
inline constexpr double kMaxCoordinate = 1e7;

enum class FieldType { Text, Real, Integer };

struct Field {
    std::string_view name;
    FieldType type;
    bool required = false;  // on create; a PATCH may omit anything
    bool writable = true;   // false: maintained by the server, shown but never accepted
    std::optional<double> min = std::nullopt;  // inclusive bounds for numbers
    std::optional<double> max = std::nullopt;
    bool positive = false;  // numbers must be > 0
    std::size_t max_length = 256;  // for text
    // Non-empty: the column is one member of a JSON object field of that name, shown there as
    // `key` (floors' "geo": {lat, lon, x, y, bearing_deg}). A group's members are given
    // together (all of them, as one object) or cleared together (null), and read back as the
    // object, or null while unset.
    std::string_view group = {};
    std::string_view key = {};
    bool angle = false;  // degrees, stored brought into [0, 360)
};

struct Kind {
    std::string_view name;      // URL segment and table name, e.g. "floors"
    std::string_view singular;  // e.g. "floor", for messages and JSON
    std::string_view parent_column;  // e.g. "building_id"; empty for maps
    std::string_view parent_kind;    // e.g. "buildings"
    std::vector<Field> fields;
    bool has_rects = false;  // rooms: a union of rectangles kept in room_rects
};

const std::vector<Kind>& kinds();
// nullptr when there is no such kind.
const Kind* find_kind(std::string_view name);
const Kind& kind(std::string_view name);  // throws std::out_of_range
// Live tracks (tracks::Service): not a resource of the hierarchy (no CRUD, not in kinds()),
// only the kind of the Change a track write puts on the feed, so other servers sharing
// PostgreSQL wake their event streams (store/pg_changes.hpp).
const Kind& track_kind();

}  // namespace locus::store
