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
          {.name = "north_offset_deg", .type = FieldType::Real, .min = -360, .max = 360}}},
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
          {.name = "scans", .type = FieldType::Integer, .writable = false}}},
    };
    return all;
}

const Kind* find_kind(std::string_view name) {
    for (const auto& k : kinds())
        if (k.name == name) return &k;
    return nullptr;
}

const Kind& kind(std::string_view name) {
    if (const Kind* k = find_kind(name)) return *k;
    throw std::out_of_range("no resource kind '" + std::string(name) + "'");
}

}  // namespace locus::store
