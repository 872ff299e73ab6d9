#pragma once
// The HTTP layer: routes, authentication, request limits, error bodies and the access log.
// Handlers parse and validate, call the store (store::Store) or the localizer
// (localize::Service), and serialise. Every route of the server is added here, in one place.
#include <httplib.h>

#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "directory/service.hpp"
#include "http/places_json.hpp"
#include "http/plans/floor_geo.hpp"
#include "http/plans/plan_answers.hpp"
#include "http/front/fair_share.hpp"
#include "http/front/front.hpp"
#include "http/radiomaps/radiomap_settings.hpp"
#include "http/front/slots.hpp"
#include "http/front/static_files.hpp"
#include "localize/service.hpp"
#include "locus/plan/route.hpp"
#include "routing/service.hpp"
#include "store/kinds.hpp"
#include "store/db.hpp"
#include "store/store.hpp"
#include "transmitters/transmitter_cache.hpp"
#include "tuning/service.hpp"

namespace locus::tracks {
class Service;
}

namespace locus::http {

struct AppOptions {
    std::string api_key;  // empty: writes need no key
    bool access_log = true;
    FrontOptions front;   // connections, timeouts, body limit
    StaticRoots web;      // the web viewer's files (static_files.cpp)
    tracks::Service* tracks = nullptr;  // live tracks (track_routes.cpp); none: no track routes
    // Radio map exports at once (each holds a connection and a read snapshot while its client
    // reads), and how long one may take before it is cut (radiomap_routes.cpp).
    std::size_t max_exports = 2;
    std::chrono::milliseconds export_timeout{600'000};
    FairShareOptions fair{};  // per-client rates (fair_share.hpp); requests with the API key are exempt
    BodyBudgetOptions bodies{};  // request bodies in flight (body_budget.hpp)
    // Answers being written: a phone's plan or radio map at once, a slow reader's few of them.
    BodyBudgetOptions answers{.total_bytes = 128u << 20, .client_bytes = 16u << 20, .small_bytes = 64u << 10, .client_small_bytes = 4u << 20};
    std::uint64_t client_requests = 8;  // requests one client has handled at once (a browser opens six connections)
    // GET /v1/maps/{id}/positions and its stream to anyone (--public-positions); else they need
    // the API key, or with no key a client on this machine (position_routes.cpp).
    bool public_positions = false;
};

class App {
public:
    // Adds every route: health and readiness, localize, then the CRUD, scan and radio-map
    // routes. httplib tries a method's routes in the order they were added, one regex match
    // each, so localize (the request a phone repeats) is found without failing a match per
    // store route first.
    App(store::Store& store, localize::Service& localizer, routing::Service& router, directory::Service& directory,
        AppOptions options);
    Front& server() { return server_; }

    // Runs a handler body, turning every failure into the JSON error shape; first the body is
    // finished (Front::finish_body: decoded, and 413 when over the limit once read).
    static void respond(const httplib::Request& req, httplib::Response& res,
                        const std::function<std::pair<int, nlohmann::json>()>& body);
    // As respond, for a 200 whose JSON text is made and kept elsewhere (plan_answers.hpp): the
    // answer is admitted (Front::admit_answer) before the text is copied into `res`.
    static void respond_text(const httplib::Request& req, httplib::Response& res,
                             const std::function<std::shared_ptr<const std::string>()>& body);
    // The same guard for a handler that writes its own answer into `res`.
    static void guarded(const httplib::Request& req, httplib::Response& res, const std::function<void()>& body);

private:
    // Admits an answer of `bytes` (Front::admit_answer), else writes its refusal into `res`.
    static bool refuse_answer(httplib::Response& res, std::size_t bytes);
    void install_middleware();
    void install_health();
    // Answers a request that must be refused before its body is read; false if it may go on.
    bool refuse_before_body(const httplib::Request& req, httplib::Response& res) const;
    // Admits the request (once per request) to its client's request slots, then its body to the
    // body budget, or answers 429 too_many_requests, 429 too_many_bodies or 503 server_busy
    // with Retry-After before the body is read.
    bool refuse_body(const httplib::Request& req, httplib::Response& res);
    void install_localize();         // localize_routes.cpp
    void install_crud();             // crud_routes.cpp
    void install_geo_routes();       // geo_routes.cpp
    void install_radiomap_routes();  // radiomap_routes.cpp
    void install_plan_routes();      // plan_routes.cpp
    void install_route_routes();     // route_routes.cpp
    void install_search_routes();    // search_routes.cpp
    void install_image_routes();     // image_routes.cpp
    void install_track_routes();     // track_routes.cpp (open, info, close, delete; then the five below)
    void install_track_fix_routes();     // track_fix_routes.cpp
    void install_track_step_routes();    // track_step_routes.cpp (thin clients)
    void install_track_stream_routes();  // track_stream_routes.cpp
    void install_track_share_routes();   // track_share_routes.cpp
    void install_relative_routes();      // relative_routes.cpp
    void install_position_routes();      // position_routes.cpp
    void install_tune_routes();      // tune_routes.cpp (from install_radiomap_routes)
    void install_transmitter_routes();  // transmitter_routes.cpp (+ trilateration, fit, generate)
    plan::Endpoint endpoint_of(const nlohmann::json& body, const char* name, std::int64_t map_id);
    plan::Endpoint place_of(const nlohmann::json& body, const char* name, std::int64_t map_id);

    store::Store& store_;
    localize::Service& localizer_;
    routing::Service& router_;
    directory::Service& directory_;
    transmitters::TransmitterCache transmitters_{store_};  // for the ranging localize and the thin clients' ranged scans
    FloorGeoCache geo_{store_};  // lat/lon in the answers of georeferenced floors
    floors::FloorPlacesCache places_{store_};  // the room and POIs near every position answered
    PositionViews views_{geo_, places_};
    PlanAnswers plan_answers_{store_};  // GET /v1/floors/{id}/plan's texts (plan_routes.cpp)
    tuning::Service tuning_{store_, settings_text()};  // tune and quality (tune_routes.cpp)
    AppOptions options_;
    Slots export_slots_{options_.max_exports};
    FairShare fair_share_{options_.fair, options_.api_key};
    BodyBudget body_budget_{options_.bodies};  // before server_: its connections' tickets point here
    BodyBudget answer_budget_{options_.answers};
    // Requests being handled, one unit each (--client-requests-in-flight).
    BodyBudget request_slots_{{.total_bytes = ~std::uint64_t{0}, .client_bytes = options_.client_requests, .small_bytes = 0,
                               .client_small_bytes = 0}};
    Front server_;
};

void write_error(httplib::Response& res, int status, const std::string& code, const std::string& message);
// 503 storage_unavailable (with Retry-After) for a storage fault (DbError::is_storage_fault).
void write_storage_unavailable(httplib::Response& res, const store::DbError& e);

}  // namespace locus::http
