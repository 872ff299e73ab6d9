// GET /v1/tracks/{a}/relative/{b}: distance, walk and bearing from track a's latest fix to
// b's (docs/tracks.md; computed by tracks/relative.hpp). a is opened by its owner's
// `X-Track-Token`, b by any of its tokens in `X-Peer-Token`.
#include <string>

#include "http/app.hpp"
#include "http/routing/route_json.hpp"
#include "http/tracks/track_json.hpp"
#include "http/tracks/track_request.hpp"
#include "http/tracks/track_respond.hpp"
#include "http/validation.hpp"
#include "tracks/relative.hpp"
#include "tracks/service.hpp"

namespace locus::http {

using nlohmann::json;

void App::install_relative_routes() {
    tracks::Service& svc = *options_.tracks;
    PositionViews& views = views_;

    server_.Get(R"(/v1/tracks/(\d+)/relative/(\d+))", [this, &svc, &views](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto a_id = parse_id(req.matches[1].str(), "track");
            const auto b_id = parse_id(req.matches[2].str(), "track");
            require_owner(svc, req, a_id, ("X-Track-Token must be the owner's token of track " + std::to_string(a_id)).c_str());
            svc.authorize(b_id, token_of(req, "X-Peer-Token"));
            tracks::Relative r;
            try {
                const auto building_of = [this](std::int64_t map_id) {
                    try {
                        return router_.building(map_id);
                    } catch (const routing::TooLarge& e) {
                        throw tracks::NoGraph(e.what());
                    }
                };
                r = tracks::relative(svc, store_, building_of, a_id, b_id);
            } catch (const tracks::Unrelated& e) {
                if (e.why == tracks::Unrelated::Why::other_map) throw ApiError(422, "other_map", e.what());
                throw ApiError(409, "no_fix", e.what());
            }
            json out = {{"from", {{"track_id", a_id}, {"fix", fix_json(r.from, views)}, {"age_s", r.from_age_s}}},
                        {"to", {{"track_id", b_id}, {"fix", fix_json(r.to, views)}, {"age_s", r.to_age_s}}},
                        {"straight_distance_m", r.straight_distance_m},
                        {"bearing_deg", r.bearing_deg},
                        {"floor_difference", r.floor_difference}};
            out["relative_bearing_deg"] = r.relative_bearing_deg ? json(*r.relative_bearing_deg) : json(nullptr);
            out["direction"] = r.relative_bearing_deg ? json(r.direction) : json(nullptr);
            if (r.route) {
                out["walking_distance_m"] = r.route->length_m;
                out["route"] = route_json(*r.route, views.geo);
            } else {
                out["walking_problem"] = r.walking_problem;
            }
            return std::pair{200, out};
        });
    });
}

}  // namespace locus::http
