// Live tracks (docs/tracks.md; the service is server/tracks/service.hpp):
//
//   POST   /v1/tracks                          {map_id, label?, fusion?, fusion_options?} -> 201 {id, token, ...}
//   POST   /v1/tracks/{id}/fixes               {fixes: [{t, floor_id, x, y, accuracy_m, heading_deg?}]}
//   POST   /v1/tracks/{id}/steps               {steps?: [{t, length_m, heading_deg}], fixes?, scans?: [{t, readings}]}
//   POST   /v1/tracks/{id}/close
//   DELETE /v1/tracks/{id}
//   GET    /v1/tracks/{id}?limit=              the track, its latest fix and trail
//   GET    /v1/tracks/{id}/events              Server-Sent Events, one `fix` event per new fix
//   POST   /v1/tracks/{id}/shares              -> 201 {id, token}
//   DELETE /v1/tracks/{id}/shares/{share}
//   GET    /v1/tracks/{a}/relative/{b}         distance, walk and bearing from a to b
//   GET    /v1/maps/{id}/positions?floor_id=   every live track's latest fix (API key)
//   GET    /v1/maps/{id}/positions/events?floor_id=   their changes, Server-Sent Events (API key)
//
// A track's token goes in `X-Track-Token` (an EventSource cannot send headers: `?token=` is
// taken too, on GETs only); the API key keeps `Authorization`. The other track of
// /relative is opened by `X-Peer-Token`. No token: 401; a token that does not open the track,
// and a track that does not exist: 403 alike.
// Eigen first: cpp-httplib (through app.hpp) pulls in <resolv.h>, whose `_res` macro breaks Eigen.
#include "tracks/fusion.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "http/app.hpp"
#include "http/json_text.hpp"
#include "http/localize/ranging_localize.hpp"
#include "http/tracks/track_anchors.hpp"
#include "http/routing/route_json.hpp"
#include "http/tracks/track_scan.hpp"
#include "http/validation.hpp"
#include "locus/plan/plan.hpp"
#include "tracks/service.hpp"
#include "tracks/token.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

constexpr std::size_t kMaxFixesPerRequest = 1000;
constexpr double kFutureSlackS = 60;  // a phone's clock may run this far ahead of the server's

json fix_json(const tracks::Fix& f, FloorGeoCache& geo) {
    json j = {{"t", f.t}, {"floor_id", f.floor_id}, {"x", f.x}, {"y", f.y}, {"accuracy_m", f.accuracy_m}};
    if (f.heading_deg) j["heading_deg"] = *f.heading_deg;
    add_lat_lon(j, geo.of_floor(f.floor_id).get(), {f.x, f.y});  // when the floor is georeferenced
    return j;
}

json track_json(const tracks::TrackInfo& t, FloorGeoCache& geo) {
    json j = {{"id", t.id},
              {"map_id", t.map_id},
              {"label", t.label},
              {"state", tracks::state_name(t.state)},
              {"created_at", t.created_at},
              {"last_fix_at", t.last_fix_at},
              {"fixes", t.fixes},
              {"fusion", tracks::fusion_method_name(t.fusion)}};
    if (!t.fusion_options.empty()) j["fusion_options"] = tracks::fusion_options_json(t.fusion_options);
    if (t.latest) j["latest"] = fix_json(*t.latest, geo);  // absent before the first fix
    if (t.ended_at) j["ended_at"] = *t.ended_at;
    return j;
}

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

// Runs a track handler: the service's refusals become their API errors.
void respond_track(const httplib::Request& req, httplib::Response& res, const std::function<std::pair<int, json>()>& body) {
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

std::string token_of(const httplib::Request& req, const char* header = "X-Track-Token") {
    std::string token = req.get_header_value(header);
    if (token.empty() && req.method == "GET" && std::string_view(header) == "X-Track-Token") token = req.get_param_value("token");
    if (token.empty()) throw ApiError(401, "unauthorized", std::string("send the track's token in the ") + header + " header");
    return token;
}

// A fix's or step's t: Unix seconds, not far ahead of the server's clock, not older than kept.
double parse_t(const json& j, const std::string& where, double retention_s) {
    const double now = tracks::Service::now();
    const double t = finite_number(j, "t", where);
    if (t > now + kFutureSlackS)
        throw invalid_field("'" + where + ".t' is " + std::to_string(t - now) + " s ahead of the server's clock (Unix seconds; at most " +
                            std::to_string(static_cast<int>(kFutureSlackS)) + " s ahead)");
    if (t < now - retention_s)
        throw invalid_field("'" + where + ".t' is older than the server keeps fixes (" + std::to_string(retention_s) + " s)");
    return t;
}

double parse_heading(const json& j, const std::string& where) {
    const double h = finite_number(j, "heading_deg", where, -360.0, 360.0);
    return h < 0 ? h + 360.0 : (h >= 360.0 ? h - 360.0 : h);
}

// An array member `name` of `body` (absent: empty unless `required`), at most `max` items.
const json* items_of(const json& body, const char* name, bool required) {
    const auto it = body.find(name);
    if (it == body.end() && !required) return nullptr;
    if (it == body.end() || !it->is_array() || (required && it->empty()))
        throw invalid_field(std::string("'") + name + "' must be a" + (required ? " non-empty" : "n") + " array");
    return &*it;
}

void check_batch_size(std::size_t n) {
    if (n > kMaxFixesPerRequest)
        throw ApiError(413, "batch_too_large", "the request holds " + std::to_string(n) + " fixes and steps; at most " +
                                                   std::to_string(kMaxFixesPerRequest) + " go in one request");
}

std::vector<tracks::Fix> parse_fix_array(const json* arr, const char* name, double retention_s) {
    std::vector<tracks::Fix> out;
    if (!arr) return out;
    out.reserve(arr->size());
    for (std::size_t i = 0; i < arr->size(); ++i) {
        const json& j = (*arr)[i];
        const std::string where = std::string(name) + "[" + std::to_string(i) + "]";
        if (!j.is_object()) throw invalid_field("'" + where + "' must be an object {t, floor_id, x, y, accuracy_m, heading_deg?}");
        only_fields(j, {"t", "floor_id", "x", "y", "accuracy_m", "heading_deg"}, where);
        tracks::Fix f;
        f.t = parse_t(j, where, retention_s);
        const auto fl = j.find("floor_id");
        if (fl == j.end() || !fl->is_number_integer() || fl->get<std::int64_t>() <= 0)
            throw invalid_field("'" + where + ".floor_id' must be a positive integer id");
        f.floor_id = fl->get<std::int64_t>();
        f.x = finite_number(j, "x", where, -plan::kMaxPlanCoordinate, plan::kMaxPlanCoordinate);
        f.y = finite_number(j, "y", where, -plan::kMaxPlanCoordinate, plan::kMaxPlanCoordinate);
        f.accuracy_m = finite_number(j, "accuracy_m", where, 0.0, 10'000.0);
        if (j.contains("heading_deg") && !j["heading_deg"].is_null()) f.heading_deg = parse_heading(j, where);
        out.push_back(f);
    }
    // Stored and streamed in time order, whatever order the batch came in.
    std::stable_sort(out.begin(), out.end(), [](const tracks::Fix& a, const tracks::Fix& b) { return a.t < b.t; });
    return out;
}

std::vector<tracks::Fix> parse_fixes(const json& body, double retention_s) {
    only_fields(body, {"fixes"}, "");
    const json* arr = items_of(body, "fixes", true);
    check_batch_size(arr->size());
    return parse_fix_array(arr, "fixes", retention_s);
}

std::vector<tracks::Step> parse_steps(const json* arr, double retention_s) {
    std::vector<tracks::Step> out;
    if (!arr) return out;
    for (std::size_t i = 0; i < arr->size(); ++i) {
        const json& j = (*arr)[i];
        const std::string where = "steps[" + std::to_string(i) + "]";
        if (!j.is_object()) throw invalid_field("'" + where + "' must be an object {t, length_m, heading_deg}");
        only_fields(j, {"t", "length_m", "heading_deg"}, where);
        out.push_back({parse_t(j, where, retention_s), finite_number(j, "length_m", where, 0.0, 3.0), parse_heading(j, where)});
    }
    std::stable_sort(out.begin(), out.end(), [](const tracks::Step& a, const tracks::Step& b) { return a.t < b.t; });
    return out;
}

// A thin client's scans {t, readings: [{type?, bssid, rss}]}, checked and in time order; they
// are localized (track_scan.hpp) only once the whole body is known good.
struct TimedScan {
    double t = 0;
    Scan readings;
    std::string where;
};
std::vector<TimedScan> parse_timed_scans(const json* arr, double retention_s) {
    std::vector<TimedScan> out;
    if (!arr) return out;
    for (std::size_t i = 0; i < arr->size(); ++i) {
        const json& j = (*arr)[i];
        const std::string where = "scans[" + std::to_string(i) + "]";
        if (!j.is_object()) throw invalid_field("'" + where + "' must be an object {t, readings: [{type, bssid, rss}]}");
        only_fields(j, {"t", "readings"}, where);
        TimedScan s{parse_t(j, where, retention_s), {}, where};
        const auto r = j.find("readings");
        if (r == j.end() || !r->is_array() || r->empty()) throw invalid_field("'" + where + ".readings' must be a non-empty array of {type, bssid, rss}");
        for (std::size_t k = 0; k < r->size(); ++k) s.readings.push_back(parse_reading((*r)[k], where + ".readings[" + std::to_string(k) + "]"));
        out.push_back(std::move(s));
    }
    std::stable_sort(out.begin(), out.end(), [](const TimedScan& a, const TimedScan& b) { return a.t < b.t; });
    return out;
}

// `fusion_options` of POST /v1/tracks: only for the Kalman methods, only the options the method
// takes (tracks/fusion_options.hpp), each a finite number in its range.
tracks::FusionOptions parse_fusion_options(const json& body, tracks::FusionMethod method) {
    tracks::FusionOptions out;
    const auto it = body.find("fusion_options");
    if (it == body.end()) return out;
    if (!tracks::ranges_scans(method))
        throw invalid_field(std::string("'fusion_options' is for the Kalman methods (kalman_trilateration, kalman_ranging, ekf_ranging); ") +
                            tracks::fusion_method_name(method) + " takes none");
    if (!it->is_object()) throw invalid_field("'fusion_options' must be an object");
    for (auto item = it->begin(); item != it->end(); ++item) {
        const std::string name = item.key();  // not a structured binding: the lambda below captures it (clang 14)
        const auto spec = std::find_if(tracks::kFusionOptions.begin(), tracks::kFusionOptions.end(),
                                       [&name](const tracks::FusionOptionSpec& s) { return name == s.name; });
        if (spec == tracks::kFusionOptions.end() || !tracks::takes(*spec, method)) {
            std::string known;
            for (const auto& s : tracks::kFusionOptions)
                if (tracks::takes(s, method)) known += std::string(known.empty() ? "" : ", ") + s.name;
            throw invalid_field("'fusion_options." + name + "' is not an option of " + tracks::fusion_method_name(method) +
                                " (it takes " + known + ")");
        }
        out.*spec->field = finite_number(*it, spec->name, "fusion_options", spec->min, spec->max);
    }
    return out;
}

// A scan on a track fused by a Kalman method: ranged on the map's transmitters as
// POST /v1/maps/{id}/localize ranges it (kalman_trilateration: trilateration, kalman_ranging and
// ekf_ranging: multilateration, the default options), the ranging fix carried for its
// covariance. ekf_ranging also carries the readings of known transmitters, its measurements,
// and takes a scan that cannot be ranged (fewer than three heard, no fix) as readings alone:
// refused only if the filter has not started (tracks::CannotFuse, the same error).
tracks::RadioFix ranged_scan_fix(const KnownTransmitters& known, tracks::FusionMethod method, double t, const Scan& readings,
                                 const std::string& where) {
    const bool ekf = method == tracks::FusionMethod::ekf_ranging;
    RangingRequest request;
    request.multilateration = method != tracks::FusionMethod::kalman_trilateration;
    request.query = match::Query::from_scans({readings});
    if (request.query.aps.empty()) throw invalid_field("'" + where + ".readings' holds no reading");
    tracks::RadioFix f;
    if (ekf) f.readings = anchor_readings(known, request.query, t);
    Ranged ranged;
    try {
        ranged = range_scan(known, request);
    } catch (const ApiError& e) {
        const std::string message = "'" + where + "': " + e.what();
        if (!ekf || e.status != 422) throw ApiError(e.status, e.code, message);
        f.t = t;
        f.unplaced = {e.code, message + "; ekf_ranging starts at a ranged scan (or a posted fix), then takes scans hearing even one or two"};
        return f;
    }
    f.t = t;
    f.floor_id = ranged.floor_id;
    f.x = ranged.fix.at.x;
    f.y = ranged.fix.at.y;
    f.accuracy_m = std::sqrt(fusion::ranging_covariance(ranged.fix).trace() / 2.0);  // its σ per axis, as a scan_fix's
    f.ranged = ranged.fix;
    return f;
}

// "ahead", "behind", "ahead, 30° left", "behind, 120° right": where b is, turned from a's
// heading (positive: clockwise, to the right).
std::string direction_text(double relative_deg) {
    const double a = std::fabs(relative_deg);
    if (a <= 10) return "ahead";
    if (a >= 170) return "behind";
    const std::string side = relative_deg > 0 ? "right" : "left";
    const std::string deg = std::to_string(static_cast<int>(std::lround(a))) + "\u00b0 " + side;
    return (a < 90 ? "ahead, " : "behind, ") + deg;
}

std::string sse_event(const char* name, const json& data) { return std::string("event: ") + name + "\ndata: " + json_text(data) + "\n\n"; }

// Turns an answered-200 response into a Server-Sent Events stream fed by `provider`.
void begin_event_stream(httplib::Response& res, httplib::ContentProviderWithoutLength provider) {
    res.body.clear();
    // respond() named the body JSON: left, it would be sent beside text/event-stream and
    // gzip would hold the events back until its buffer filled.
    res.headers.erase("Content-Type");
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider("text/event-stream", std::move(provider));
}

}  // namespace

void App::install_track_routes() {
    tracks::Service& svc = *options_.tracks;
    FloorGeoCache& geo = geo_;

    server_.Post("/v1/tracks", [this, &svc, &geo](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const json body = parse_object(req.body);
            only_fields(body, {"map_id", "label", "fusion", "fusion_options"}, "");
            const auto m = body.find("map_id");
            if (m == body.end() || !m->is_number_integer() || m->get<std::int64_t>() <= 0)
                throw invalid_field("'map_id' must be a positive integer id");
            const std::string label = optional_string(body, "label", "", 100).value_or("");
            auto fusion = tracks::FusionMethod::walk_pf;
            if (const auto f = body.find("fusion"); f != body.end()) {
                const auto named = f->is_string() ? tracks::fusion_method_of(f->get<std::string>()) : std::nullopt;
                if (!named)
                    throw invalid_field("'fusion' must be \"walk_pf\" (the default), \"particle\", \"kalman_trilateration\" "
                                        "(or its deprecated alias \"kalman_seed\"), \"kalman_ranging\" or \"ekf_ranging\"");
                fusion = *named;
            }
            const auto fusion_options = parse_fusion_options(body, fusion);
            tracks::Opened o;
            try {
                o = svc.open(m->get<std::int64_t>(), label, fusion, fusion_options, fair_share_.client(req));
            } catch (const store::NotFound& e) {
                throw invalid_field(std::string("'map_id': ") + e.what());
            }
            json out = track_json(o.info, geo);
            out["token"] = o.token;
            out["ttl_s"] = svc.options().ttl_s;
            out["retention_s"] = svc.options().retention_s;
            return std::pair{201, out};
        });
    });

    server_.Post(R"(/v1/tracks/(\d+)/fixes)", [&svc, &geo](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            if (svc.authorize(id, token_of(req)) != tracks::Access::owner)
                throw ApiError(403, "forbidden", "a share token reads a track; only its owner's token posts fixes");
            const auto fixes = parse_fixes(parse_object(req.body), svc.options().retention_s);
            if (const auto floor = svc.misplaced_floor(id, fixes))
                throw invalid_field("floor " + std::to_string(*floor) + " is not a floor of track " + std::to_string(id) + "'s map");
            const auto posted = svc.post(id, fixes);
            json out = {{"stored", posted.stored}, {"duplicates", posted.duplicates}};
            if (posted.latest) out["latest"] = fix_json(*posted.latest, geo);
            return std::pair{200, out};
        });
    });

    // Thin clients: raw PDR steps, radio fixes and scans in, the particle filter's fixes out (and
    // stored). A scan is localized as the map's localize endpoint would, and is the filter's fix.
    server_.Post(R"(/v1/tracks/(\d+)/steps)", [this, &svc, &geo](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            if (svc.authorize(id, token_of(req)) != tracks::Access::owner)
                throw ApiError(403, "forbidden", "a share token reads a track; only its owner's token posts steps");
            const json body = parse_object(req.body);
            only_fields(body, {"steps", "fixes", "scans"}, "");
            const json* steps_json = items_of(body, "steps", false);
            const json* fixes_json = items_of(body, "fixes", false);
            const json* scans_json = items_of(body, "scans", false);
            const auto count = [](const json* a) { return a ? a->size() : 0; };
            const std::size_t n = count(steps_json) + count(fixes_json) + count(scans_json);
            if (n == 0) throw invalid_field("send 'steps' (PDR steps {t, length_m, heading_deg}), 'fixes' (radio fixes) and/or 'scans' ({t, readings})");
            check_batch_size(n);
            const auto steps = parse_steps(steps_json, svc.options().retention_s);
            std::vector<tracks::RadioFix> radio;
            for (const auto& f : parse_fix_array(fixes_json, "fixes", svc.options().retention_s)) radio.emplace_back(f);
            const auto scans = parse_timed_scans(scans_json, svc.options().retention_s);
            json scan_fixes = json::array();
            std::optional<KnownTransmitters> known;  // read once for the batch
            std::shared_ptr<const tracks::FloorAnchors> anchors;
            const auto track = svc.info(id);
            // An ekf_ranging filter (re)started by this request, even by steps alone (resumed at
            // the latest stored fix), takes its floor's transmitters as anchors; a Kalman track
            // ranges its scans on them.
            const bool anchored = track.fusion == tracks::FusionMethod::ekf_ranging && track.state == tracks::State::live;
            if (anchored || (!scans.empty() && tracks::ranges_scans(track.fusion)))
                known = known_transmitters(store_, transmitters_, true, track.map_id, RangingRequest{}.phone_height);
            if (anchored) anchors = floor_anchors(*known);
            if (!scans.empty()) {
                // The particle filters take the radio map's match.
                std::shared_ptr<const localize::Snapshot> snapshot;
                if (!known) snapshot = localizer_.lookup(localize::Service::Scope::map, track.map_id);
                for (const auto& sc : scans) {
                    if (snapshot)
                        radio.emplace_back(scan_fix(*snapshot, sc.t, sc.readings, sc.where));
                    else
                        radio.push_back(ranged_scan_fix(*known, track.fusion, sc.t, sc.readings, sc.where));
                    if (!radio.back().unplaced) scan_fixes.push_back(fix_json(radio.back(), geo));
                }
                std::stable_sort(radio.begin(), radio.end(), [](const tracks::Fix& a, const tracks::Fix& b) { return a.t < b.t; });
            }
            std::vector<tracks::Fix> placed;
            for (const auto& r : radio)
                if (!r.unplaced) placed.push_back(r);
            if (const auto floor = svc.misplaced_floor(id, placed))
                throw invalid_field("floor " + std::to_string(*floor) + " is not a floor of track " + std::to_string(id) + "'s map");
            std::pair<tracks::Posted, std::vector<tracks::Fix>> done;
            try {
                done = svc.post_raw(id, steps, radio, std::move(anchors));
            } catch (const tracks::CannotFuse& e) {
                throw ApiError(422, e.code, e.what());
            } catch (const std::invalid_argument& e) {
                throw ApiError(422, "cannot_fuse", e.what());
            }
            json fused = json::array();
            for (const auto& f : done.second) fused.push_back(fix_json(f, geo));
            json out = {{"stored", done.first.stored}, {"duplicates", done.first.duplicates}, {"fused", fused}};
            if (!scans.empty()) out["scan_fixes"] = std::move(scan_fixes);
            if (done.first.latest) out["latest"] = fix_json(*done.first.latest, geo);
            return std::pair{200, out};
        });
    });

    // Actions whose body is optional: `curl -X POST` with no body gets no 411.
    server_.allow_no_body("POST", R"(/v1/tracks/(\d+)/close)");
    server_.allow_no_body("POST", R"(/v1/tracks/(\d+)/shares)");
    server_.Post(R"(/v1/tracks/(\d+)/close)", [&svc, &geo](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            if (svc.authorize(id, token_of(req)) != tracks::Access::owner)
                throw ApiError(403, "forbidden", "only the track's owner closes it");
            return std::pair{200, track_json(svc.close(id), geo)};
        });
    });

    server_.Delete(R"(/v1/tracks/(\d+))", [&svc](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            if (svc.authorize(id, token_of(req)) != tracks::Access::owner)
                throw ApiError(403, "forbidden", "only the track's owner deletes it");
            svc.remove(id);
            return std::pair{204, json()};
        });
    });

    server_.Get(R"(/v1/tracks/(\d+))", [&svc, &geo](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            svc.authorize(id, token_of(req));
            std::size_t limit = 100;
            if (req.has_param("limit")) limit = static_cast<std::size_t>(parse_query_integer(req.get_param_value("limit"), "limit", 0, 1000));
            json out = track_json(svc.info(id), geo);
            json trail = json::array();
            for (const auto& f : svc.trail(id, limit)) trail.push_back(fix_json(f, geo));
            out["trail"] = std::move(trail);
            return std::pair{200, out};
        });
    });

    server_.Get(R"(/v1/tracks/(\d+)/events)", [this, &svc, &geo](const httplib::Request& req, httplib::Response& res) {
        std::shared_ptr<tracks::Service::Stream> stream;
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            stream = svc.open_stream(id, token_of(req), fair_share_.client(req));
            return std::pair{200, json()};
        });
        if (!stream) return;  // refused: res holds the error
        begin_event_stream(res, [&svc, &geo, stream](std::size_t, httplib::DataSink& sink) {
            const auto events = svc.next_events(*stream);
            std::string out;
            for (const auto& f : events.fixes) out += sse_event("fix", fix_json(f, geo));
            if (events.fixes.empty() && !events.ended) out = ": heartbeat\n\n";
            if (events.ended) out += sse_event("end", json{{"reason", "the track is no longer live, or the server is stopping"}});
            if (!sink.write(out.data(), out.size())) return false;
            if (events.ended) sink.done();
            return true;
        });
    });

    server_.Post(R"(/v1/tracks/(\d+)/shares)", [&svc](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            if (svc.authorize(id, token_of(req)) != tracks::Access::owner)
                throw ApiError(403, "forbidden", "only the track's owner shares it");
            if (!req.body.empty()) only_fields(parse_object(req.body), {}, "");
            const auto share = svc.add_share(id);
            return std::pair{201, json{{"id", share.id}, {"track_id", share.track_id}, {"token", share.token}}};
        });
    });

    server_.Delete(R"(/v1/tracks/(\d+)/shares/(\d+))", [&svc](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto id = parse_id(req.matches[1].str(), "track");
            const auto share_id = parse_id(req.matches[2].str(), "share");
            if (svc.authorize(id, token_of(req)) != tracks::Access::owner)
                throw ApiError(403, "forbidden", "only the track's owner revokes a share");
            svc.revoke_share(id, share_id);
            return std::pair{204, json()};
        });
    });

    server_.Get(R"(/v1/tracks/(\d+)/relative/(\d+))", [this, &svc, &geo](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto a_id = parse_id(req.matches[1].str(), "track");
            const auto b_id = parse_id(req.matches[2].str(), "track");
            if (svc.authorize(a_id, token_of(req)) != tracks::Access::owner)
                throw ApiError(403, "forbidden", "X-Track-Token must be the owner's token of track " + std::to_string(a_id));
            svc.authorize(b_id, token_of(req, "X-Peer-Token"));
            const auto a = svc.info(a_id), b = svc.info(b_id);
            if (a.map_id != b.map_id) throw ApiError(422, "other_map", "tracks " + std::to_string(a_id) + " and " + std::to_string(b_id) + " are on different maps");
            if (!a.latest || !b.latest)
                throw ApiError(409, "no_fix", "track " + std::to_string(a.latest ? b_id : a_id) + " has no fix yet");
            const tracks::Fix& fa = *a.latest;
            const tracks::Fix& fb = *b.latest;
            const double dx = fb.x - fa.x, dy = fb.y - fa.y;
            const auto level = [this](std::int64_t floor_id) { return store_.get(store::kind("floors"), floor_id).fields.get<std::int64_t>("level"); };
            const double now = tracks::Service::now();
            double bearing = std::atan2(dx, dy) * 180.0 / std::numbers::pi;  // clockwise from +y, as headings
            if (bearing < 0) bearing += 360.0;
            json out = {{"from", {{"track_id", a_id}, {"fix", fix_json(fa, geo)}, {"age_s", now - fa.t}}},
                        {"to", {{"track_id", b_id}, {"fix", fix_json(fb, geo)}, {"age_s", now - fb.t}}},
                        {"straight_distance_m", std::hypot(dx, dy)},
                        {"bearing_deg", bearing},
                        {"floor_difference", level(fb.floor_id) - level(fa.floor_id)}};
            if (fa.heading_deg) {
                double rel = bearing - *fa.heading_deg;
                while (rel > 180) rel -= 360;
                while (rel <= -180) rel += 360;
                out["relative_bearing_deg"] = rel;
                out["direction"] = direction_text(rel);
            } else {
                out["relative_bearing_deg"] = nullptr;
                out["direction"] = nullptr;
            }
            try {
                const auto building = router_.building(a.map_id);
                thread_local plan::RouteScratch scratch;
                const plan::Route r = plan::route(*building, {fa.floor_id, {fa.x, fa.y}}, {fb.floor_id, {fb.x, fb.y}}, {}, scratch);
                if (r.status == plan::RouteStatus::ok) {
                    out["walking_distance_m"] = r.length_m;
                    out["route"] = route_json(r, geo);
                } else {
                    out["walking_problem"] = plan::to_string(r.status);
                }
            } catch (const store::NotFound& e) {
                out["walking_problem"] = e.what();
            }
            return std::pair{200, out};
        });
    });

    // Everyone's position: for the operator, so the API key is asked even on these GETs.
    const auto positions_scope = [this](const httplib::Request& req, httplib::Response& res) {
        if (!options_.api_key.empty()) {
            const std::string auth = req.get_header_value("Authorization");
            if (!auth.starts_with("Bearer ") || !tracks::same_hash(auth.substr(7), options_.api_key)) {
                res.set_header("WWW-Authenticate", "Bearer");
                throw ApiError(401, "unauthorized", "positions of every track need 'Authorization: Bearer <api key>'");
            }
        }
        const auto map_id = parse_id(req.matches[1].str(), "map");
        (void)store_.get(store::kind("maps"), map_id);  // 404 for an unknown map
        std::optional<std::int64_t> floor;
        if (req.has_param("floor_id")) floor = parse_query_integer(req.get_param_value("floor_id"), "floor_id", 1, INT64_MAX);
        return std::pair{map_id, floor};
    };

    server_.Get(R"(/v1/maps/(\d+)/positions)", [positions_scope, &svc, &geo](const httplib::Request& req, httplib::Response& res) {
        respond_track(req, res, [&] {
            const auto [map_id, floor] = positions_scope(req, res);
            const double now = tracks::Service::now();
            json positions = json::array();
            for (const auto& t : svc.live_on_map(map_id, floor))
                positions.push_back({{"track_id", t.id}, {"label", t.label}, {"fix", fix_json(*t.latest, geo)}, {"age_s", now - t.latest->t}});
            return std::pair{200, json{{"map_id", map_id}, {"positions", positions}}};
        });
    });

    // The live layer's stream: `position` {track_id, label, fix} for each new latest fix on the
    // map (or floor_id), `leave` {track_id, floor_id|null} when a shown track goes to another
    // floor (its floor) or ends (null). The first events are every live track's position.
    server_.Get(R"(/v1/maps/(\d+)/positions/events)", [this, positions_scope, &svc, &geo](const httplib::Request& req, httplib::Response& res) {
        std::shared_ptr<tracks::Service::MapStream> stream;
        respond_track(req, res, [&] {
            const auto scope = positions_scope(req, res);
            stream = svc.open_map_stream(scope.first, scope.second, fair_share_.client(req));
            return std::pair{200, json()};
        });
        if (!stream) return;  // refused: res holds the error
        begin_event_stream(res, [&svc, &geo, stream](std::size_t, httplib::DataSink& sink) {
            const auto batch = svc.next_map_events(*stream);
            std::string out;
            for (const auto& e : batch.events) {
                if (e.kind == tracks::MapEvent::Kind::position) {
                    out += sse_event("position", json{{"track_id", e.track_id}, {"label", e.label}, {"fix", fix_json(*e.fix, geo)}});
                } else {
                    json floor = nullptr;
                    if (e.fix) floor = e.fix->floor_id;
                    out += sse_event("leave", json{{"track_id", e.track_id}, {"floor_id", floor}});
                }
            }
            if (batch.events.empty() && !batch.ended) out = ": heartbeat\n\n";
            if (batch.ended) out += sse_event("end", json{{"reason", "the server is stopping"}});
            if (!sink.write(out.data(), out.size())) return false;
            if (batch.ended) sink.done();
            return true;
        });
    });
}

}  // namespace locus::http
