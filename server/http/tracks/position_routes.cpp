// Everyone's position on a map, for the operator (docs/tracks.md): these GETs need the API
// key, or on a server without one a client on this machine (through the trusted proxies,
// FairShare::local); --public-positions opens them to anyone.
//
//   GET    /v1/maps/{id}/positions?floor_id=          every live track's latest fix
//   GET    /v1/maps/{id}/positions/events?floor_id=   their changes, Server-Sent Events
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>

#include "http/app.hpp"
#include "http/tracks/event_stream.hpp"
#include "http/tracks/track_json.hpp"
#include "http/tracks/track_respond.hpp"
#include "http/validation.hpp"
#include "tracks/service.hpp"
#include "tracks/token.hpp"

namespace locus::http {

using nlohmann::json;

void App::install_position_routes() {
    tracks::Service& svc = *options_.tracks;
    PositionViews& views = views_;

    const auto positions_scope = [this](const httplib::Request& req, httplib::Response& res) {
        if (options_.public_positions) {
            // Anyone's, as the operator chose.
        } else if (!options_.api_key.empty()) {
            const std::string auth = req.get_header_value("Authorization");
            if (!auth.starts_with("Bearer ") || !tracks::same_hash(auth.substr(7), options_.api_key)) {
                res.set_header("WWW-Authenticate", "Bearer");
                throw ApiError(401, "unauthorized", "positions of every track need 'Authorization: Bearer <api key>'");
            }
        } else if (!fair_share_.local(req)) {
            throw ApiError(403, "forbidden",
                           "positions of every track are the operator's: on a server without --api-key they are answered only to "
                           "a client on the server's own machine (behind a proxy, name it with --trusted-proxy); start the "
                           "server with --api-key, or with --public-positions to show them to anyone");
        }
        const auto map_id = parse_id(req.matches[1].str(), "map");
        (void)store_.get(store::kind("maps"), map_id);  // 404 for an unknown map
        std::optional<std::int64_t> floor;
        if (req.has_param("floor_id")) floor = parse_query_integer(req.get_param_value("floor_id"), "floor_id", 1, INT64_MAX);
        return std::pair{map_id, floor};
    };

    server_.Get(R"(/v1/maps/(\d+)/positions)", [positions_scope, &svc, &views](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto [map_id, floor] = positions_scope(req, res);
            const double now = tracks::Service::now();
            json positions = json::array();
            for (const auto& t : svc.live_on_map(map_id, floor))
                positions.push_back({{"track_id", t.id}, {"label", t.label}, {"fix", fix_json(*t.latest, views)}, {"age_s", now - t.latest->t}});
            return std::pair{200, json{{"map_id", map_id}, {"positions", positions}}};
        });
    });

    // The live layer's stream: `position` {track_id, label, fix} for each new latest fix on the
    // map (or floor_id), `leave` {track_id, floor_id|null} when a shown track goes to another
    // floor (its floor) or ends (null). The first events are every live track's position.
    server_.Get(R"(/v1/maps/(\d+)/positions/events)", [this, positions_scope, &svc, &views](const httplib::Request& req, httplib::Response& res) {
        std::shared_ptr<tracks::Service::MapStream> stream;
        respond_track(req, res, [&] {
            const auto scope = positions_scope(req, res);
            stream = svc.open_map_stream(scope.first, scope.second, fair_share_.client(req));
            return std::pair{200, json()};
        });
        if (!stream) return;  // refused: res holds the error
        begin_event_stream(res, [&svc, &views, stream](std::size_t, httplib::DataSink& sink) {
            const auto next = next_batch(
                sink, svc.options().heartbeat_s, [&](double wait_s) { return svc.next_map_events(*stream, wait_s); },
                [](const tracks::MapEvents& b) { return !b.events.empty() || b.ended; });
            if (!next) return false;  // the reader hung up
            const tracks::MapEvents& batch = *next;
            std::string out;
            for (const auto& e : batch.events) {
                if (e.kind == tracks::MapEvent::Kind::position) {
                    out += sse_event("position", json{{"track_id", e.track_id}, {"label", e.label}, {"fix", fix_json(*e.fix, views)}});
                } else {
                    json floor = nullptr;
                    if (e.fix) floor = e.fix->floor_id;
                    out += sse_event("leave", json{{"track_id", e.track_id}, {"floor_id", floor}});
                }
            }
            if (batch.events.empty() && !batch.ended) out = ": heartbeat\n\n";
            if (batch.ended) out += sse_event("end", json{{"reason", batch.evicted ? kEvicted : "the server is stopping"}});
            if (!sink.write(out.data(), out.size())) return false;
            if (batch.ended) sink.done();
            return true;
        });
    });
}

}  // namespace locus::http
