// POST /v1/radiomaps/{id}/localize and POST /v1/maps/{id}/localize: one scan against one
// radio map's or one map's index; on a map, "track_id" (with the track's token) matches in
// that live track's subarea (docs/tracks.md "Subarea").
#include <string>
#include <tuple>

#include "http/app.hpp"
#include "http/localize/localize_answer.hpp"
#include "http/localize/localize_request.hpp"
#include "http/localize/ranging_localize.hpp"
#include "http/tracks/track_request.hpp"
#include "http/tracks/track_respond.hpp"
#include "http/validation.hpp"
#include "tracks/scan_area.hpp"

namespace locus::http {

namespace {

// The subarea of the live track a localize on map `map_id` names: none when the track has no fix
// yet or its subarea is off. Only its owner's token names it. The time since its latest fix is
// the server's (since the fix was posted): the fix's own t is the phone's clock.
std::optional<match::Near> track_subarea(tracks::Service* svc, const httplib::Request& req, std::int64_t map_id, std::int64_t track_id) {
    if (!svc) throw invalid_field("'track_id': this server keeps no live tracks");
    try {
        require_owner(*svc, req, track_id, "only the track's owner's token names it in a localize");
        const tracks::TrackInfo track = svc->info(track_id);
        if (track.map_id != map_id)
            throw invalid_field("'track_id': track " + std::to_string(track_id) + " is on map " + std::to_string(track.map_id));
        if (track.state != tracks::State::live)
            throw ApiError(409, "track_closed", "track " + std::to_string(track_id) + " is closed: only a live track's subarea is used");
        if (!track.latest || !track.fusion_options.subarea.value_or(true)) return std::nullopt;
        tracks::Fix latest = *track.latest;
        latest.t = track.last_fix_at;
        return tracks::subarea_round(latest, tracks::Service::now());
    } catch (const tracks::Refused& e) {
        throw api_error_of(e);
    }
}

}  // namespace

void App::install_localize() {
    using Scope = localize::Service::Scope;
    for (const auto& [collection, what, scope] :
         {std::tuple{"radiomaps", "radiomap", Scope::radiomap}, std::tuple{"maps", "map", Scope::map}}) {
        server_.Post("/v1/" + std::string(collection) + R"(/(\d+)/localize)",
                     // Init-captures: clang before 16 cannot capture structured bindings.
                     [this, what = what, scope = scope](const httplib::Request& req, httplib::Response& res) {
                         guarded(req, res, [&] {
                             const auto id = parse_id(req.matches[1].str(), what);
                             if (const auto ranging = parse_ranging_request(req.body)) {
                                 res.set_content(ranging_answer(store_, transmitters_, views_, scope == Scope::map, id, *ranging), "application/json");
                                 return;
                             }
                             auto request = parse_localize_request(req.body);
                             if (request.track_id) {
                                 if (scope != Scope::map) throw invalid_field("'track_id' is for POST /v1/maps/{id}/localize");
                                 request.track_subarea = track_subarea(options_.tracks, req, id, *request.track_id);
                             }
                             // Moved in: set_content would copy the answer. As set_content
                             // does, any earlier Content-Type goes.
                             res.body = answer(*localizer_.lookup(scope, id), request, &geo_, &places_);
                             res.headers.erase("Content-Type");
                             res.set_header("Content-Type", "application/json");
                         });
                     });
    }
}

}  // namespace locus::http
