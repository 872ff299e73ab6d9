#include "http/tracks/track_respond.hpp"

#include <cmath>
#include <string>

#include "http/app.hpp"

namespace locus::http {

ApiError api_error_of(const tracks::Refused& e) {
    switch (e.reason) {
        case tracks::Reason::forbidden: return {403, "forbidden", e.what()};
        case tracks::Reason::gone: return {404, "not_found", e.what()};
        case tracks::Reason::closed: return {409, "track_closed", e.what()};
        case tracks::Reason::busy: return {503, "server_busy", e.what()};
        case tracks::Reason::full: return {409, "track_full", e.what()};
        case tracks::Reason::too_many_tracks: return {503, "too_many_tracks", e.what()};
        case tracks::Reason::too_many_streams: return {429, "too_many_streams", e.what()};
        case tracks::Reason::client_live_tracks: return {429, "too_many_live_tracks", e.what()};
        case tracks::Reason::client_streams: return {429, "too_many_client_streams", e.what()};
    }
    return {500, "internal", e.what()};
}

void respond_track(const httplib::Request& req, httplib::Response& res, const std::function<std::pair<int, nlohmann::json>()>& body) {
    App::respond(req, res, [&] {
        try {
            return body();
        } catch (const tracks::Refused& e) {
            if (e.reason == tracks::Reason::busy || e.reason == tracks::Reason::too_many_streams) res.set_header("Retry-After", "1");
            // Every slot is a live track's: they free as tracks close, no use retrying at once.
            if (e.reason == tracks::Reason::too_many_tracks) res.set_header("Retry-After", "60");
            // The client's own track that goes quiet first closes at --track-ttl; a stream of its
            // own frees only when it closes one, so it is told to look again in a while.
            if (e.reason == tracks::Reason::client_live_tracks)
                res.set_header("Retry-After", std::to_string(static_cast<long long>(std::ceil(e.retry_after_s))));
            if (e.reason == tracks::Reason::client_streams) res.set_header("Retry-After", "10");
            throw api_error_of(e);
        }
    });
}

}  // namespace locus::http
