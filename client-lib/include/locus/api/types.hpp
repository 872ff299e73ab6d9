#pragma once
// The REST resources as plain structs. Ids are the server's; 0 means "not created yet".
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/radio_map.hpp"

namespace locus::api {

struct MapInfo {
    std::int64_t id = 0;
    std::string name;
    std::string description;
};

struct BuildingInfo {
    std::int64_t id = 0;
    std::int64_t map_id = 0;
    std::string name;
    std::string description;
};

struct FloorInfo {
    std::int64_t id = 0;
    std::int64_t building_id = 0;
    std::string name;
    int level = 0;
    double width = 0.0;
    double height = 0.0;
    double north_offset_deg = 0.0;
};

struct RoomInfo {
    std::int64_t id = 0;
    std::int64_t floor_id = 0;
    std::string name;
    std::vector<Rect> rects;
};

struct PoiInfo {
    std::int64_t id = 0;
    std::int64_t floor_id = 0;
    std::string name;
    std::string kind;
    double x = 0.0;
    double y = 0.0;
};

struct RadioMapInfo {
    std::int64_t id = 0;
    std::int64_t floor_id = 0;
    std::string name;
    std::string description;
};

struct RpInfo {
    std::int64_t id = 0;
    std::int64_t radiomap_id = 0;
    std::string name;
    double x = 0.0;
    double y = 0.0;
    std::int64_t scans = 0;
    std::vector<Measurement> measurements;  // filled only where the server sends them
};

// One upload to one RP: raw scans (the server aggregates) or ready aggregates.
struct ScanUpload {
    std::optional<std::string> upload_id;  // a repeated id for the same RP is acknowledged and ignored
    std::vector<Scan> scans;
    std::vector<Measurement> measurements;  // used when `scans` is empty
};

struct UploadResult {
    bool applied = false;  // false: the upload id had already been merged into this RP
    RpInfo rp;
};

struct LocalizeRequest {
    // Unset: the body names no algorithm and the server's default applies.
    std::optional<std::string> algorithm;
    std::vector<Scan> scans;
    nlohmann::json options = nlohmann::json::object();
};

struct LocalizeResult {
    double x = 0.0;
    double y = 0.0;
    std::int64_t floor_id = 0;
    std::int64_t building_id = 0;
    std::optional<std::string> room;
    double score = 0.0;
    int matched_aps = 0;
    nlohmann::json raw;  // the whole answer, candidates included
};

// JSON shapes of the API (request bodies and answers).
nlohmann::json to_json(const Scan& scan);
nlohmann::json to_json(const Measurement& m);
nlohmann::json to_json(const ScanUpload& upload);
nlohmann::json to_json(const LocalizeRequest& request);
MapInfo map_from_json(const nlohmann::json& j);
BuildingInfo building_from_json(const nlohmann::json& j);
FloorInfo floor_from_json(const nlohmann::json& j);
RoomInfo room_from_json(const nlohmann::json& j);
PoiInfo poi_from_json(const nlohmann::json& j);
RadioMapInfo radiomap_from_json(const nlohmann::json& j);
RpInfo rp_from_json(const nlohmann::json& j);
Measurement measurement_from_json(const nlohmann::json& j);
LocalizeResult localize_result_from_json(const nlohmann::json& j);

}  // namespace locus::api
