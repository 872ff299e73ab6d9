// Live tracks (docs/tracks.md; the service is server/tracks/service.hpp):
//
//   POST   /v1/tracks                          {map_id, label?, fusion?, fusion_options?} -> 201 {id, token, ...}
//   POST   /v1/tracks/{id}/fixes               track_fix_routes.cpp
//   POST   /v1/tracks/{id}/steps               track_step_routes.cpp (thin clients)
//   POST   /v1/tracks/{id}/close
//   DELETE /v1/tracks/{id}
//   GET    /v1/tracks/{id}?limit=              the track, its latest fix and trail
//   GET    /v1/tracks/{id}/events              track_stream_routes.cpp
//   POST   /v1/tracks/{id}/shares, DELETE …/shares/{share}   track_share_routes.cpp
//   GET    /v1/tracks/{a}/relative/{b}         relative_routes.cpp
//   GET    /v1/maps/{id}/positions[/events]    position_routes.cpp (API key)
//
// A track's token goes in `X-Track-Token` (an EventSource cannot send headers: `?token=` is
// taken too, on GETs only); the API key keeps `Authorization`. The other track of
// /relative is opened by `X-Peer-Token`. No token: 401; a token that does not open the track,
// and a track that does not exist: 403 alike (track_request.hpp, track_respond.hpp).
#include <string>

#include "http/app.hpp"
#include "http/tracks/track_json.hpp"
#include "http/tracks/track_request.hpp"
#include "http/tracks/track_respond.hpp"
#include "http/validation.hpp"
#include "tracks/service.hpp"

namespace locus::http {

using nlohmann::json;

void App::install_track_routes() {
    tracks::Service& svc = *options_.tracks;
    PositionViews& views = views_;

    server_.Post("/v1/tracks", [this, &svc, &views](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const OpenRequest open = parse_open_request(parse_object(req.body));
            tracks::Opened o;
            try {
                o = svc.open(open.map_id, open.label, open.fusion, open.fusion_options, fair_share_.client(req));
            } catch (const store::NotFound& e) {
                throw invalid_field(std::string("'map_id': ") + e.what());
            }
            json out = track_json(o.info, views);
            out["token"] = o.token;
            out["ttl_s"] = svc.options().ttl_s;
            out["retention_s"] = svc.options().retention_s;
            return std::pair{201, out};
        });
    });

    install_track_fix_routes();
    install_track_step_routes();

    // An action whose body is optional: `curl -X POST` with no body gets no 411.
    server_.allow_no_body("POST", R"(/v1/tracks/(\d+)/close)");
    server_.Post(R"(/v1/tracks/(\d+)/close)", [&svc, &views](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            require_owner(svc, req, id, "only the track's owner closes it");
            return std::pair{200, track_json(svc.close(id), views)};
        });
    });

    server_.Delete(R"(/v1/tracks/(\d+))", [&svc](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            require_owner(svc, req, id, "only the track's owner deletes it");
            svc.remove(id);
            return std::pair{204, json()};
        });
    });

    server_.Get(R"(/v1/tracks/(\d+))", [&svc, &views](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            svc.authorize(id, token_of(req));
            std::size_t limit = 100;
            if (req.has_param("limit")) limit = static_cast<std::size_t>(parse_query_integer(req.get_param_value("limit"), "limit", 0, 1000));
            json out = track_json(svc.info(id), views);
            json trail = json::array();
            for (const auto& f : svc.trail(id, limit)) trail.push_back(fix_json(f, views));
            out["trail"] = std::move(trail);
            return std::pair{200, out};
        });
    });

    install_track_stream_routes();
    install_track_share_routes();
    install_relative_routes();
    install_position_routes();
}

}  // namespace locus::http
