// A track's shares (docs/tracks.md): read-only tokens its owner hands out and revokes.
//
//   POST   /v1/tracks/{id}/shares              -> 201 {id, track_id, token}
//   DELETE /v1/tracks/{id}/shares/{share}
#include "http/app.hpp"
#include "http/tracks/track_request.hpp"
#include "http/tracks/track_respond.hpp"
#include "http/validation.hpp"
#include "tracks/service.hpp"

namespace locus::http {

using nlohmann::json;

void App::install_track_share_routes() {
    tracks::Service& svc = *options_.tracks;

    // The body is optional: `curl -X POST` with no body gets no 411.
    server_.allow_no_body("POST", R"(/v1/tracks/(\d+)/shares)");
    server_.Post(R"(/v1/tracks/(\d+)/shares)", [&svc](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            require_owner(svc, req, id, "only the track's owner shares it");
            if (!req.body.empty()) only_fields(parse_object(req.body), {}, "");
            const auto share = svc.add_share(id);
            return std::pair{201, json{{"id", share.id}, {"track_id", share.track_id}, {"token", share.token}}};
        });
    });

    server_.Delete(R"(/v1/tracks/(\d+)/shares/(\d+))", [&svc](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            const auto share_id = parse_id(req.matches[2].str(), "share");
            require_owner(svc, req, id, "only the track's owner revokes a share");
            svc.revoke_share(id, share_id);
            return std::pair{204, json()};
        });
    });
}

}  // namespace locus::http
