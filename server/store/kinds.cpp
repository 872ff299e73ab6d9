#include "store/kinds.hpp"

#include <stdexcept>
#include <string>

namespace locus::store {

namespace {

Field name_field() { return {.name = "name", .type = FieldType::Text, .required = true, .max_length = 200}; }
Field description_field() { return {.name = "description", .type = FieldType::Text, .max_length = 4000}; }
Field coordinate(std::string_view n) {
    return {.name = n, .type = FieldType::Real, .required = true, .min = -kMaxCoordinate, .max = kMaxCoordinate};
}
// A member of a floor's georeference (schema/014_floor_geo.sql, docs/geo.md).
Field geo(std::string_view column, std::string_view key, double min, double max, bool angle = false) {
    return {.name = column, .type = FieldType::Real, .min = min, .max = max, .group = "geo", .key = key, .angle = angle};
}
}  // namespace

const std::vector<Kind>& kinds() {
    static const std::vector<Kind> all = {
        {"maps", "map", "", "", {name_field(), description_field()}},
        {"buildings", "building", "map_id", "maps", {name_field(), description_field()}},
        {"floors",
         "floor",
         "building_id",
         "buildings",
         {name_field(),
          {.name = "level", .type = FieldType::Integer, .required = true, .min = -1000, .max = 1000},
          {.name = "width", .type = FieldType::Real, .required = true, .max = kMaxCoordinate, .positive = true},
          {.name = "height", .type = FieldType::Real, .required = true, .max = kMaxCoordinate, .positive = true},
          {.name = "north_offset_deg", .type = FieldType::Real, .min = -360, .max = 360},
          // Height of the floor above the building's reference, for barometric floor changes.
          {.name = "elevation_m", .type = FieldType::Real, .min = -1000, .max = 10000},
          geo("geo_lat", "lat", -90, 90),
          geo("geo_lon", "lon", -180, 180),
          geo("geo_x", "x", -kMaxCoordinate, kMaxCoordinate),
          geo("geo_y", "y", -kMaxCoordinate, kMaxCoordinate),
          geo("geo_bearing_deg", "bearing_deg", -360, 360, true)}},
        {"rooms", "room", "floor_id", "floors", {name_field()}, true},
        {"pois",
         "poi",
         "floor_id",
         "floors",
         {name_field(), {.name = "kind", .type = FieldType::Text, .max_length = 64}, coordinate("x"), coordinate("y")}},
        {"radiomaps", "radiomap", "floor_id", "floors", {name_field(), description_field()}},
        {"rps",
         "rp",
         "radiomap_id",
         "radiomaps",
         {name_field(), coordinate("x"), coordinate("y"),
          {.name = "scans", .type = FieldType::Integer, .writable = false},
          // 1: modelled from the floor's transmitters (POST …/radiomaps/generate), not surveyed
          {.name = "generated", .type = FieldType::Integer, .writable = false},
          // when a scan upload last changed the RP (schema 010); null until one does
          {.name = "last_upload_at", .type = FieldType::Text, .writable = false}}},
        // schema/009_transmitters.sql; http/transmitters/transmitter_routes.cpp checks what a field alone
        // cannot (type, the bssid's form, the position within the floor).
        {"transmitters",
         "transmitter",
         "floor_id",
         "floors",
         {{.name = "name", .type = FieldType::Text, .max_length = 200},
          {.name = "type", .type = FieldType::Text, .required = true, .max_length = 16},
          {.name = "bssid", .type = FieldType::Text, .required = true, .max_length = 64},
          coordinate("x"),
          coordinate("y"),
          {.name = "z", .type = FieldType::Real, .min = -100, .max = 1000},
          {.name = "tx_power", .type = FieldType::Real, .required = true, .min = -120, .max = 30},
          {.name = "path_loss_exponent", .type = FieldType::Real, .min = 1, .max = 8},
          {.name = "wall_attenuation", .type = FieldType::Real, .min = 0, .max = 60}}},
    };
    return all;
}

const Kind* find_kind(std::string_view name) {
    for (const auto& k : kinds())
        if (k.name == name) return &k;
    return nullptr;
}

const Kind& track_kind() {
    static const Kind k{"tracks", "track", "map_id", "maps", {}};
    return k;
}

const Kind& kind(std::string_view name) {
    if (const Kind* k = find_kind(name)) return *k;
    throw std::out_of_range("no resource kind '" + std::string(name) + "'");
}

}  // namespace locus::store
