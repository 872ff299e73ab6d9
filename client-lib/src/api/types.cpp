#include "locus/api/types.hpp"

namespace locus::api {

using nlohmann::json;

namespace {
std::string text_or(const json& j, const char* key, const std::string& fallback = "") {
    const auto it = j.find(key);
    return it != j.end() && it->is_string() ? it->get<std::string>() : fallback;
}
template <typename T>
T number_or(const json& j, const char* key, T fallback = T{}) {
    const auto it = j.find(key);
    return it != j.end() && it->is_number() ? it->get<T>() : fallback;
}
}  // namespace

json to_json(const Scan& scan) {
    json arr = json::array();
    for (const auto& r : scan) {
        json reading = {{"bssid", r.bssid}, {"rss", r.rss}};
        if (r.type != "wifi") reading["type"] = r.type;  // the server's default; keeps bodies small
        arr.push_back(std::move(reading));
    }
    return arr;
}

json to_json(const Measurement& m) {
    return {{"type", m.type}, {"bssid", m.bssid}, {"mean", m.stats.mean}, {"variance", m.stats.variance},
            {"count", m.stats.count}};
}

json to_json(const ScanUpload& upload) {
    json body = json::object();
    if (upload.upload_id) body["upload_id"] = *upload.upload_id;
    if (!upload.scans.empty()) {
        json scans = json::array();
        for (const auto& s : upload.scans) scans.push_back(to_json(s));
        body["scans"] = std::move(scans);
    } else {
        json ms = json::array();
        for (const auto& m : upload.measurements) ms.push_back(to_json(m));
        body["measurements"] = std::move(ms);
    }
    return body;
}

json to_json(const LocalizeRequest& request) {
    json scans = json::array();
    for (const auto& s : request.scans) scans.push_back(to_json(s));
    json body = {{"scans", std::move(scans)}};
    if (request.algorithm) body["algorithm"] = *request.algorithm;
    if (!request.options.empty()) body["options"] = request.options;
    return body;
}

MapInfo map_from_json(const json& j) {
    return {number_or<std::int64_t>(j, "id"), text_or(j, "name"), text_or(j, "description")};
}

BuildingInfo building_from_json(const json& j) {
    return {number_or<std::int64_t>(j, "id"), number_or<std::int64_t>(j, "map_id"), text_or(j, "name"),
            text_or(j, "description")};
}

FloorInfo floor_from_json(const json& j) {
    FloorInfo f;
    f.id = number_or<std::int64_t>(j, "id");
    f.building_id = number_or<std::int64_t>(j, "building_id");
    f.name = text_or(j, "name");
    f.level = number_or<int>(j, "level");
    f.width = number_or<double>(j, "width");
    f.height = number_or<double>(j, "height");
    f.north_offset_deg = number_or<double>(j, "north_offset_deg");
    return f;
}

RoomInfo room_from_json(const json& j) {
    RoomInfo r;
    r.id = number_or<std::int64_t>(j, "id");
    r.floor_id = number_or<std::int64_t>(j, "floor_id");
    r.name = text_or(j, "name");
    if (const auto it = j.find("rects"); it != j.end() && it->is_array())
        for (const auto& rect : *it)
            r.rects.push_back({number_or<double>(rect, "xmin"), number_or<double>(rect, "ymin"),
                               number_or<double>(rect, "xmax"), number_or<double>(rect, "ymax")});
    return r;
}

PoiInfo poi_from_json(const json& j) {
    return {number_or<std::int64_t>(j, "id"), number_or<std::int64_t>(j, "floor_id"), text_or(j, "name"),
            text_or(j, "kind"), number_or<double>(j, "x"), number_or<double>(j, "y")};
}

RadioMapInfo radiomap_from_json(const json& j) {
    return {number_or<std::int64_t>(j, "id"), number_or<std::int64_t>(j, "floor_id"), text_or(j, "name"),
            text_or(j, "description")};
}

Measurement measurement_from_json(const json& j) {
    Measurement m;
    m.type = text_or(j, "type", "wifi");
    m.bssid = text_or(j, "bssid");
    m.stats.mean = number_or<double>(j, "mean");
    m.stats.variance = number_or<double>(j, "variance");
    m.stats.count = number_or<std::int64_t>(j, "count");
    return m;
}

RpInfo rp_from_json(const json& j) {
    RpInfo rp;
    rp.id = number_or<std::int64_t>(j, "id");
    rp.radiomap_id = number_or<std::int64_t>(j, "radiomap_id");
    rp.name = text_or(j, "name");
    rp.x = number_or<double>(j, "x");
    rp.y = number_or<double>(j, "y");
    rp.scans = number_or<std::int64_t>(j, "scans");
    if (const auto it = j.find("measurements"); it != j.end() && it->is_array())
        for (const auto& m : *it) rp.measurements.push_back(measurement_from_json(m));
    return rp;
}

LocalizeResult localize_result_from_json(const json& j) {
    LocalizeResult r;
    r.x = number_or<double>(j, "x");
    r.y = number_or<double>(j, "y");
    r.floor_id = number_or<std::int64_t>(j, "floor_id");
    r.building_id = number_or<std::int64_t>(j, "building_id");
    if (const auto it = j.find("room"); it != j.end() && it->is_object()) r.room = text_or(*it, "name");
    r.score = number_or<double>(j, "score");
    r.matched_aps = number_or<int>(j, "matched_aps");
    r.raw = j;
    return r;
}

}  // namespace locus::api
