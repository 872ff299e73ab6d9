#pragma once
// The REST resources as plain structs. Ids are the server's; 0 means "not created yet".
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/match/localize.hpp"
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

// The API's rooms, POIs and RPs are the core's, each with the id of what it belongs to.
struct RoomInfo : Room {
    std::int64_t floor_id = 0;
};

struct PoiInfo : Poi {
    std::int64_t floor_id = 0;
};

struct RadioMapInfo {
    std::int64_t id = 0;
    std::int64_t floor_id = 0;
    std::string name;
    std::string description;
};

// `measurements` is filled only where the server sends them (one RP, an upload's answer).
struct RpInfo : ReferencePoint {
    std::int64_t radiomap_id = 0;
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

// The matcher's result as the server answers it, with the room that holds the position.
struct LocalizeResult : match::Result {
    std::optional<std::string> room;  // the room's name
    nlohmann::json raw;               // the whole answer
};

// JSON shapes of the API (request bodies and answers), found by nlohmann's ADL: json j = x;
// x = j.get<T>(). Reading an answer, a field that is missing, null (the server sends null for
// an unset optional field such as a description) or of another JSON type keeps its default.
// NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT would throw on the null, so types.cpp
// defines the readers with a lenient macro of the same make.
void to_json(nlohmann::json& j, const ScanUpload& upload);
void to_json(nlohmann::json& j, const LocalizeRequest& request);
void from_json(const nlohmann::json& j, MapInfo& map);
void from_json(const nlohmann::json& j, BuildingInfo& building);
void from_json(const nlohmann::json& j, FloorInfo& floor);
void from_json(const nlohmann::json& j, RoomInfo& room);
void from_json(const nlohmann::json& j, PoiInfo& poi);
void from_json(const nlohmann::json& j, RadioMapInfo& radiomap);
void from_json(const nlohmann::json& j, RpInfo& rp);
void from_json(const nlohmann::json& j, LocalizeResult& result);

}  // namespace locus::api

// The core's types as the API spells them. They live here, beside the client, because the
// core includes no JSON library; nlohmann finds them by ADL in the types' namespace.
namespace locus {

void to_json(nlohmann::json& j, const Reading& reading);  // "type" only when not wifi
void to_json(nlohmann::json& j, const Measurement& m);    // flat: type, bssid, mean, variance, count
void from_json(const nlohmann::json& j, Measurement& m);
void to_json(nlohmann::json& j, const Rect& rect);
void from_json(const nlohmann::json& j, Rect& rect);

}  // namespace locus

namespace locus::match {
void from_json(const nlohmann::json& j, Candidate& candidate);  // a localize answer's candidate
}  // namespace locus::match
