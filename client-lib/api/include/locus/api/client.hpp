#pragma once
// A small typed client for the Locus REST API (docs/spec.md §2–§4): the map hierarchy, RP scan
// uploads, radio-map export/import, floor plans and localization.
//
// One Client holds one keep-alive connection and is not thread-safe: give each thread its own.
// Every request has connect/read timeouts; network failures, 5xx and 429 are retried with
// exponential back-off (RetryPolicy), 4xx never. A failure that survives the retries throws
// ApiError (the server answered) or NetworkError (it did not).
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "locus/api/error.hpp"
#include "locus/api/retry.hpp"
#include "locus/api/tracks.hpp"
#include "locus/api/types.hpp"
#include "locus/plan/plan.hpp"

namespace locus::api {

struct ClientOptions {
    std::string base_url = "http://127.0.0.1:8080";
    std::string api_key;  // sent as "Authorization: Bearer KEY" when not empty
    std::chrono::milliseconds connect_timeout{2000};
    std::chrono::milliseconds read_timeout{30000};
    RetryPolicy retry;
};

// The server's list answer: one page of rows.
struct Page {
    std::vector<nlohmann::json> items;
    std::int64_t total = 0;
};

class Client {
public:
    explicit Client(ClientOptions options);
    ~Client();
    Client(Client&&) noexcept;
    Client& operator=(Client&&) noexcept;

    const ClientOptions& options() const { return options_; }
    // Requests sent again after a retryable failure, over this client's life.
    std::int64_t retries() const { return retries_; }

    // Generic verbs: `path` starts with '/'. Return the parsed JSON body (null for 204).
    nlohmann::json get(const std::string& path);
    nlohmann::json post(const std::string& path, const nlohmann::json& body);
    nlohmann::json put(const std::string& path, const nlohmann::json& body);  // a whole document, e.g. a floor's plan
    nlohmann::json patch(const std::string& path, const nlohmann::json& body);
    void del(const std::string& path);

    bool healthy();  // one GET /health, no retries

    // Every row of a collection, following limit/offset pages of `page_size` (≤ 1000).
    std::vector<nlohmann::json> list_all(const std::string& collection_path, int page_size = 1000);

    // Hierarchy.
    MapInfo create_map(const std::string& name, const std::string& description = "");
    std::vector<MapInfo> maps();
    BuildingInfo create_building(std::int64_t map_id, const std::string& name, const std::string& description = "");
    std::vector<BuildingInfo> buildings(std::int64_t map_id);
    FloorInfo create_floor(const FloorInfo& floor);  // floor.building_id names the parent
    std::vector<FloorInfo> floors(std::int64_t building_id);
    FloorInfo floor(std::int64_t floor_id);
    RoomInfo create_room(const RoomInfo& room);
    std::vector<RoomInfo> rooms(std::int64_t floor_id);
    PoiInfo create_poi(const PoiInfo& poi);
    std::vector<PoiInfo> pois(std::int64_t floor_id);
    RadioMapInfo create_radiomap(std::int64_t floor_id, const std::string& name, const std::string& description = "");
    std::vector<RadioMapInfo> radiomaps(std::int64_t floor_id);
    RadioMapInfo radiomap(std::int64_t radiomap_id);
    RpInfo create_rp(std::int64_t radiomap_id, const std::string& name, double x, double y);
    std::vector<RpInfo> rps(std::int64_t radiomap_id);
    RpInfo rp(std::int64_t rp_id);  // with its measurements

    // Find by name (through the paginated list) or create: what makes imports re-runnable.
    // A concurrent creator winning the race (409) is resolved by reading the list again.
    MapInfo ensure_map(const std::string& name, const std::string& description = "");
    BuildingInfo ensure_building(std::int64_t map_id, const std::string& name, const std::string& description = "");
    // An existing floor is returned as stored (its size is not changed).
    FloorInfo ensure_floor(const FloorInfo& floor);
    RadioMapInfo ensure_radiomap(std::int64_t floor_id, const std::string& name, const std::string& description = "");
    RpInfo ensure_rp(std::int64_t radiomap_id, const std::string& name, double x, double y);

    // Merges scans into an RP. Without an upload_id the client makes one up, so that its own
    // retries of this call can never be counted twice.
    UploadResult upload(std::int64_t rp_id, const ScanUpload& upload);

    // A floor's plan (GET /v1/floors/{id}/plan, read with the GeoJSON codec the server
    // uses); nullopt when the floor has none. An unknown floor throws the server's 404
    // not_found, as every other call does.
    std::optional<plan::Plan> plan(std::int64_t floor_id);
    // Replaces the floor's plan (PUT); returns the plan as stored. A plan the server refuses
    // throws its 422 invalid_plan naming the feature.
    plan::Plan put_plan(std::int64_t floor_id, const plan::Plan& plan);

    nlohmann::json export_radiomap(std::int64_t radiomap_id);  // locus-radiomap/1 document
    RadioMapInfo import_radiomap(std::int64_t floor_id, const nlohmann::json& document);

    LocalizeResult localize_radiomap(std::int64_t radiomap_id, const LocalizeRequest& request);
    LocalizeResult localize_map(std::int64_t map_id, const LocalizeRequest& request);

    // Live tracks (tracks.cpp; README "Live tracks"). A TrackKey is a track's id and a token
    // that opens it: the owner's, or a share's for the reads.
    OpenedTrack open_track(std::int64_t map_id, const std::string& label = "");
    // Retrying is safe: a fix whose t is stored already counts as a duplicate.
    TrackPosted post_fixes(const TrackKey& track, const std::vector<TrackFix>& fixes);
    // A thin client's batch (POST /v1/tracks/{id}/steps: steps, fixes, scans, pressure, gnss):
    // the server runs the track's filter; its answer (`fused`, `scan_fixes`, ...) as it is.
    nlohmann::json post_steps(const TrackKey& track, const nlohmann::json& batch);
    TrackState track(const TrackKey& track, int trail_limit = 100);
    void close_track(const TrackKey& track);
    void delete_track(const TrackKey& track);
    TrackShare share_track(const TrackKey& track);
    void revoke_share(const TrackKey& track, std::int64_t share_id);
    // Where `other` is, seen from `track` (its owner's key): the server's answer as it is.
    nlohmann::json relative(const TrackKey& track, const TrackKey& other);
    // Every live track's latest fix on the map (needs the API key when the server has one).
    std::vector<TrackPosition> positions(std::int64_t map_id, std::optional<std::int64_t> floor_id = std::nullopt);

private:
    using Headers = std::vector<std::pair<std::string, std::string>>;
    nlohmann::json send(const char* method, const std::string& path, const std::string* body, const Headers& headers = {});

    ClientOptions options_;
    struct Connection;
    std::unique_ptr<Connection> conn_;
    std::int64_t retries_ = 0;
    std::uint64_t upload_counter_ = 0;
};

}  // namespace locus::api
