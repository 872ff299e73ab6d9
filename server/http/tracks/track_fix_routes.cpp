// POST /v1/tracks/{id}/fixes {fixes: [{t, floor_id, x, y, accuracy_m, heading_deg?}]}: a phone
// that runs client-lib posts its fused fixes (docs/tracks.md). The owner's token only; the
// body's bytes are the client's (FairShare::charge_track_bytes).
#include <string>

#include "http/app.hpp"
#include "http/tracks/track_json.hpp"
#include "http/tracks/track_request.hpp"
#include "http/tracks/track_respond.hpp"
#include "http/validation.hpp"
#include "tracks/service.hpp"

namespace locus::http {

using nlohmann::json;

void App::install_track_fix_routes() {
    tracks::Service& svc = *options_.tracks;
    PositionViews& views = views_;

    server_.Post(R"(/v1/tracks/(\d+)/fixes)", [this, &svc, &views](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            require_owner(svc, req, id, "a share token reads a track; only its owner's token posts fixes");
            fair_share_.charge_track_bytes(req);
            const auto fixes = parse_fixes(parse_object(req.body), svc.options().retention_s);
            if (const auto floor = svc.misplaced_floor(id, fixes))
                throw invalid_field("floor " + std::to_string(*floor) + " is not a floor of track " + std::to_string(id) + "'s map");
            const auto posted = svc.post(id, fixes);
            json out = {{"stored", posted.stored}, {"duplicates", posted.duplicates}};
            if (posted.latest) out["latest"] = fix_json(*posted.latest, views);
            return std::pair{200, out};
        });
    });
}

}  // namespace locus::http
