#include "locus/api/types.hpp"

#include <type_traits>

namespace {

using nlohmann::json;

// `field` keeps its value unless `j` has `key` with a value of the field's JSON kind: a
// string (for any type made from text), a number, or an array (of elements each read as
// leniently). Any other field type is a compile error, never a field silently left unread.
template <typename T>
void read_field(const json& j, const char* key, T& field) {
    const auto it = j.find(key);
    if (it == j.end()) return;
    if constexpr (std::is_arithmetic_v<T>) {
        if (it->is_number()) field = it->template get<T>();
    } else if constexpr (std::is_constructible_v<T, std::string>) {
        if (it->is_string()) field = T(it->template get<std::string>());
    } else {
        static_assert(requires { typename T::value_type; }, "read_field reads text, numbers and arrays");
        if (it->is_array()) it->get_to(field);
    }
}

// A bssid as text, whatever type holds it.
const std::string& bssid_text(const std::string& s) { return s; }

// The API spells a position and an RSS aggregate flat, as fields of the object holding them.
void read_field(const json& j, const char*, locus::Point& at) {
    read_field(j, "x", at.x);
    read_field(j, "y", at.y);
}
void read_field(const json& j, const char*, locus::RssStats& stats) {
    read_field(j, "mean", stats.mean);
    read_field(j, "variance", stats.variance);
    read_field(j, "count", stats.count);
}

}  // namespace

// NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT's from_json, built the same way, but each
// field read with read_field, so a null or mistyped field keeps its default (see types.hpp).
#define LOCUS_API_READ_FIELD(field) read_field(json_, #field, value_.field);
#define LOCUS_API_FROM_JSON(Type, ...)                   \
    void from_json(const json& json_, Type& value_) { \
        NLOHMANN_JSON_EXPAND(NLOHMANN_JSON_PASTE(LOCUS_API_READ_FIELD, __VA_ARGS__)) }

namespace locus {

void to_json(json& j, const Reading& reading) {
    j = {{"bssid", bssid_text(reading.bssid)}, {"rss", reading.rss}};
    if (reading.type != "wifi") j["type"] = reading.type;  // the server's default; keeps bodies small
}

void to_json(json& j, const Measurement& m) {
    j = {{"type", m.type}, {"bssid", bssid_text(m.bssid)}, {"mean", m.stats.mean}, {"variance", m.stats.variance},
         {"count", m.stats.count}};
}

void to_json(json& j, const Rect& rect) {
    j = {{"xmin", rect.xmin}, {"ymin", rect.ymin}, {"xmax", rect.xmax}, {"ymax", rect.ymax}};
}

LOCUS_API_FROM_JSON(Measurement, type, bssid, stats)
LOCUS_API_FROM_JSON(Rect, xmin, ymin, xmax, ymax)

}  // namespace locus

namespace locus::match {
LOCUS_API_FROM_JSON(Candidate, rp_id, at, score, floor_id, building_id, matched_aps)
}  // namespace locus::match

namespace locus::api {

void to_json(json& j, const ScanUpload& upload) {
    j = json::object();
    if (upload.upload_id) j["upload_id"] = *upload.upload_id;
    if (!upload.scans.empty()) j["scans"] = upload.scans;
    else j["measurements"] = upload.measurements;
}

void to_json(json& j, const LocalizeRequest& request) {
    j = {{"scans", request.scans}};
    if (request.algorithm) j["algorithm"] = *request.algorithm;
    if (!request.options.empty()) j["options"] = request.options;
}

LOCUS_API_FROM_JSON(MapInfo, id, name, description)
LOCUS_API_FROM_JSON(BuildingInfo, id, map_id, name, description)
LOCUS_API_FROM_JSON(FloorInfo, id, building_id, name, level, width, height, north_offset_deg)
LOCUS_API_FROM_JSON(RoomInfo, id, floor_id, name, rects)
LOCUS_API_FROM_JSON(PoiInfo, id, floor_id, name, kind, at)
LOCUS_API_FROM_JSON(RadioMapInfo, id, floor_id, name, description)
LOCUS_API_FROM_JSON(RpInfo, id, radiomap_id, name, at, scans, measurements)

void from_json(const json& j, LocalizeResult& result) {
    read_field(j, "", result.at);
    read_field(j, "floor_id", result.floor_id);
    read_field(j, "building_id", result.building_id);
    if (const auto it = j.find("room"); it != j.end() && it->is_object()) read_field(*it, "name", result.room.emplace());
    read_field(j, "rps", result.rp_ids);
    read_field(j, "score", result.score);
    read_field(j, "matched_aps", result.matched_aps);
    read_field(j, "algorithm", result.algorithm);
    read_field(j, "candidates", result.candidates);
    result.raw = j;
}

}  // namespace locus::api
