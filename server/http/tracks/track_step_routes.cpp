// POST /v1/tracks/{id}/steps {steps?: [{t, length_m, heading_deg}], fixes?, scans?: [{t, readings}],
// pressure?: [{t, hpa}], gnss?: [{t, lat, lon, accuracy_m}]}: thin clients post raw PDR steps,
// radio fixes, scans, their barometer's samples and GNSS fixes; the track's filter's fixes come back
// (and are stored). The work is tracks/map_scans.hpp's post_steps; the body's bytes and its
// scans to localize are the client's (FairShare::charge_track_bytes, charge_localizations).
// Eigen first: cpp-httplib (through app.hpp) pulls in <resolv.h>, whose `_res` macro breaks Eigen.
#include "tracks/map_scans.hpp"

#include "http/app.hpp"
#include "http/tracks/track_json.hpp"
#include "http/tracks/track_request.hpp"
#include "http/tracks/track_respond.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

void App::install_track_step_routes() {
    tracks::Service& svc = *options_.tracks;
    PositionViews& views = views_;

    server_.Post(R"(/v1/tracks/(\d+)/steps)", [this, &svc, &views](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            require_owner(svc, req, id, "a share token reads a track; only its owner's token posts steps");
            fair_share_.charge_track_bytes(req);  // before the parse: a client past its budget costs no more
            const auto input = parse_steps_request(parse_object(req.body), svc.options().retention_s);
            fair_share_.charge_localizations(req, input.scans.size());
            tracks::StepsDone done;
            try {
                done = tracks::post_steps(svc, id, input, {store_, transmitters_, localizer_, views.geo});
            } catch (const tracks::CannotFuse& e) {
                throw ApiError(422, e.code, e.what());
            } catch (const tracks::ForeignFloor& e) {
                throw invalid_field(e.what());
            }
            json fused = json::array();
            for (const auto& f : done.fused) fused.push_back(fix_json(f, views));
            json out = {{"stored", done.posted.stored}, {"duplicates", done.posted.duplicates}, {"fused", fused}};
            if (!input.scans.empty()) {
                json scan_fixes = json::array();
                for (std::size_t i = 0; i < done.scan_fixes.size(); ++i) scan_fixes.push_back(scan_fix_json(done.scan_fixes[i], done.scan_areas[i], views));
                out["scan_fixes"] = std::move(scan_fixes);
            }
            if (done.rss_offset_db) out["rss_offset_db"] = *done.rss_offset_db;
            if (done.posted.latest) out["latest"] = fix_json(*done.posted.latest, views);
            return std::pair{200, out};
        });
    });
}

}  // namespace locus::http
