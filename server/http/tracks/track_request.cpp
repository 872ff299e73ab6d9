#include "http/tracks/track_request.hpp"

#include <algorithm>
#include <string_view>

#include "http/api_error.hpp"
#include "http/validation.hpp"
#include "locus/plan/plan.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

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
    const double w = h < 0 ? h + 360.0 : (h >= 360.0 ? h - 360.0 : h);
    // A tiny negative heading rounds to exactly 360 when shifted; north is 0.
    return w >= 360.0 ? 0.0 : w;
}

// An array member `name` of `body` (absent: null unless `required`).
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
// are localized (tracks/thin_client.hpp) only once the whole body is known good.
std::vector<tracks::TimedScan> parse_timed_scans(const json* arr, double retention_s) {
    std::vector<tracks::TimedScan> out;
    if (!arr) return out;
    for (std::size_t i = 0; i < arr->size(); ++i) {
        const json& j = (*arr)[i];
        const std::string where = "scans[" + std::to_string(i) + "]";
        if (!j.is_object()) throw invalid_field("'" + where + "' must be an object {t, readings: [{type, bssid, rss}]}");
        only_fields(j, {"t", "readings"}, where);
        tracks::TimedScan s{parse_t(j, where, retention_s), {}, where};
        const auto r = j.find("readings");
        if (r == j.end() || !r->is_array() || r->empty()) throw invalid_field("'" + where + ".readings' must be a non-empty array of {type, bssid, rss}");
        for (std::size_t k = 0; k < r->size(); ++k) s.readings.push_back(parse_reading((*r)[k], where + ".readings[" + std::to_string(k) + "]"));
        out.push_back(std::move(s));
    }
    std::stable_sort(out.begin(), out.end(), [](const tracks::TimedScan& a, const tracks::TimedScan& b) { return a.t < b.t; });
    return out;
}

// The barometer's samples {t, hpa}, in time order.
std::vector<tracks::Pressure> parse_pressure(const json* arr, double retention_s) {
    std::vector<tracks::Pressure> out;
    if (!arr) return out;
    if (arr->size() > kMaxPressurePerRequest)
        throw ApiError(413, "batch_too_large", "the request holds " + std::to_string(arr->size()) + " pressure samples; at most " +
                                                   std::to_string(kMaxPressurePerRequest) + " go in one request");
    out.reserve(arr->size());
    for (std::size_t i = 0; i < arr->size(); ++i) {
        const json& j = (*arr)[i];
        const std::string where = "pressure[" + std::to_string(i) + "]";
        if (!j.is_object()) throw invalid_field("'" + where + "' must be an object {t, hpa}");
        only_fields(j, {"t", "hpa"}, where);
        out.push_back({parse_t(j, where, retention_s), finite_number(j, "hpa", where, kMinPressureHpa, kMaxPressureHpa)});
    }
    std::stable_sort(out.begin(), out.end(), [](const tracks::Pressure& a, const tracks::Pressure& b) { return a.t < b.t; });
    return out;
}

// The GNSS receiver's fixes {t, lat, lon, accuracy_m}, in time order (the filter takes them on
// the track's floor: tracks/fusion.hpp). An accuracy of 0 claims a certainty no receiver has.
std::vector<tracks::Gnss> parse_gnss(const json* arr, double retention_s) {
    std::vector<tracks::Gnss> out;
    if (!arr) return out;
    if (arr->size() > kMaxGnssPerRequest)
        throw ApiError(413, "batch_too_large", "the request holds " + std::to_string(arr->size()) + " GNSS fixes; at most " +
                                                   std::to_string(kMaxGnssPerRequest) + " go in one request");
    out.reserve(arr->size());
    for (std::size_t i = 0; i < arr->size(); ++i) {
        const json& j = (*arr)[i];
        const std::string where = "gnss[" + std::to_string(i) + "]";
        if (!j.is_object()) throw invalid_field("'" + where + "' must be an object {t, lat, lon, accuracy_m}");
        only_fields(j, {"t", "lat", "lon", "accuracy_m"}, where);
        tracks::Gnss g;
        g.t = parse_t(j, where, retention_s);
        g.lat = finite_number(j, "lat", where, -90.0, 90.0);
        g.lon = finite_number(j, "lon", where, -180.0, 180.0);
        g.accuracy_m = finite_number(j, "accuracy_m", where, 0.0, kMaxGnssAccuracyM);
        if (!(g.accuracy_m > 0.0))
            throw ApiError(422, "out_of_range", "'" + where + ".accuracy_m' = 0 is not a receiver's accuracy: it must be positive (m, at most " +
                                                    std::to_string(static_cast<int>(kMaxGnssAccuracyM)) + ")");
        out.push_back(g);
    }
    std::stable_sort(out.begin(), out.end(), [](const tracks::Gnss& a, const tracks::Gnss& b) { return a.t < b.t; });
    return out;
}

// `fusion_options` of POST /v1/tracks: for the Kalman methods and walk_pf, only the options the
// method takes (tracks/fusion_options.hpp), each a finite number in its range; walk_pf's
// `subarea` a boolean.
tracks::FusionOptions parse_fusion_options(const json& body, tracks::FusionMethod method) {
    tracks::FusionOptions out;
    const auto it = body.find("fusion_options");
    if (it == body.end()) return out;
    if (std::none_of(tracks::kFusionOptions.begin(), tracks::kFusionOptions.end(),
                     [&](const tracks::FusionOptionSpec& s) { return tracks::takes(s, method); }))
        throw invalid_field(std::string("'fusion_options' is for the Kalman methods (kalman_trilateration, kalman_ranging, ekf_ranging) "
                                        "and walk_pf; ") +
                            tracks::fusion_method_name(method) + " takes none");
    if (!it->is_object()) throw invalid_field("'fusion_options' must be an object");
    for (auto item = it->begin(); item != it->end(); ++item) {
        const std::string name = item.key();  // not a structured binding: the lambda below captures it (clang 14)
        if (name == tracks::kSubareaOption && method == tracks::FusionMethod::walk_pf) {
            if (!item->is_boolean()) throw invalid_field("'fusion_options.subarea' must be true or false");
            out.subarea = item->get<bool>();
            continue;
        }
        const auto spec = std::find_if(tracks::kFusionOptions.begin(), tracks::kFusionOptions.end(),
                                       [&name](const tracks::FusionOptionSpec& s) { return name == s.name; });
        if (spec == tracks::kFusionOptions.end() || !tracks::takes(*spec, method)) {
            std::string known;
            for (const auto& s : tracks::kFusionOptions)
                if (tracks::takes(s, method)) known += std::string(known.empty() ? "" : ", ") + s.name;
            if (method == tracks::FusionMethod::walk_pf) known += std::string(", ") + tracks::kSubareaOption;
            throw invalid_field("'fusion_options." + name + "' is not an option of " + tracks::fusion_method_name(method) +
                                " (it takes " + known + ")");
        }
        out.*spec->field = finite_number(*it, spec->name, "fusion_options", spec->min, spec->max);
    }
    return out;
}

}  // namespace

std::string token_of(const httplib::Request& req, const char* header) {
    std::string token = req.get_header_value(header);
    if (token.empty() && req.method == "GET" && std::string_view(header) == "X-Track-Token") token = req.get_param_value("token");
    if (token.empty()) throw ApiError(401, "unauthorized", std::string("send the track's token in the ") + header + " header");
    return token;
}

void require_owner(tracks::Service& svc, const httplib::Request& req, std::int64_t id, const char* refusal) {
    if (svc.authorize(id, token_of(req)) != tracks::Access::owner) throw ApiError(403, "forbidden", refusal);
}

OpenRequest parse_open_request(const json& body) {
    only_fields(body, {"map_id", "label", "fusion", "fusion_options"}, "");
    const auto m = body.find("map_id");
    if (m == body.end() || !m->is_number_integer() || m->get<std::int64_t>() <= 0)
        throw invalid_field("'map_id' must be a positive integer id");
    OpenRequest out;
    out.map_id = m->get<std::int64_t>();
    out.label = optional_string(body, "label", "", 100).value_or("");
    if (const auto f = body.find("fusion"); f != body.end()) {
        const auto named = f->is_string() ? tracks::fusion_method_of(f->get<std::string>()) : std::nullopt;
        if (!named)
            throw invalid_field("'fusion' must be \"walk_pf\" (the default), \"particle\", \"kalman_trilateration\" "
                                "(or its deprecated alias \"kalman_seed\"), \"kalman_ranging\" or \"ekf_ranging\"");
        out.fusion = *named;
    }
    out.fusion_options = parse_fusion_options(body, out.fusion);
    return out;
}

std::vector<tracks::Fix> parse_fixes(const json& body, double retention_s) {
    only_fields(body, {"fixes"}, "");
    const json* arr = items_of(body, "fixes", true);
    check_batch_size(arr->size());
    return parse_fix_array(arr, "fixes", retention_s);
}

tracks::StepsInput parse_steps_request(const json& body, double retention_s) {
    only_fields(body, {"steps", "fixes", "scans", "pressure", "gnss"}, "");
    const json* steps = items_of(body, "steps", false);
    const json* fixes = items_of(body, "fixes", false);
    const json* scans = items_of(body, "scans", false);
    const json* pressure = items_of(body, "pressure", false);
    const json* gnss = items_of(body, "gnss", false);
    const auto count = [](const json* a) { return a ? a->size() : 0; };
    const std::size_t n = count(steps) + count(fixes) + count(scans);
    if (n + count(pressure) + count(gnss) == 0)
        throw invalid_field("send 'steps' (PDR steps {t, length_m, heading_deg}), 'fixes' (radio fixes), 'scans' ({t, readings}), "
                            "'pressure' ({t, hpa}) and/or 'gnss' ({t, lat, lon, accuracy_m})");
    check_batch_size(n);
    tracks::StepsInput out;
    out.steps = parse_steps(steps, retention_s);
    out.fixes = parse_fix_array(fixes, "fixes", retention_s);
    out.scans = parse_timed_scans(scans, retention_s);
    out.pressure = parse_pressure(pressure, retention_s);
    out.gnss = parse_gnss(gnss, retention_s);
    return out;
}

}  // namespace locus::http
