// GET /v1/tracks/{id}/events: Server-Sent Events, one `fix` event per new fix of the track, an
// `end` event when it is no longer live (docs/tracks.md). The owner's or a share's token.
#include <memory>

#include "http/app.hpp"
#include "http/tracks/event_stream.hpp"
#include "http/tracks/track_json.hpp"
#include "http/tracks/track_request.hpp"
#include "http/tracks/track_respond.hpp"
#include "http/validation.hpp"
#include "tracks/service.hpp"

namespace locus::http {

using nlohmann::json;

void App::install_track_stream_routes() {
    tracks::Service& svc = *options_.tracks;
    PositionViews& views = views_;

    server_.Get(R"(/v1/tracks/(\d+)/events)", [this, &svc, &views](const httplib::Request& req, httplib::Response& res) {
        std::shared_ptr<tracks::Service::Stream> stream;
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            stream = svc.open_stream(id, token_of(req), fair_share_.client(req));
            return std::pair{200, json()};
        });
        if (!stream) return;  // refused: res holds the error
        begin_event_stream(res, [&svc, &views, stream](std::size_t, httplib::DataSink& sink) {
            const auto next = next_batch(
                sink, svc.options().heartbeat_s, [&](double wait_s) { return svc.next_events(*stream, wait_s); },
                [](const tracks::Events& e) { return !e.fixes.empty() || e.ended; });
            if (!next) return false;  // the reader hung up
            const tracks::Events& events = *next;
            std::string out;
            for (const auto& f : events.fixes) out += sse_event("fix", fix_json(f, views));
            if (events.fixes.empty() && !events.ended) out = ": heartbeat\n\n";
            if (events.ended)
                out += sse_event("end", json{{"reason", events.evicted ? kEvicted : "the track is no longer live, or the server is stopping"}});
            if (!sink.write(out.data(), out.size())) return false;
            if (events.ended) sink.done();
            return true;
        });
    });
}

}  // namespace locus::http
