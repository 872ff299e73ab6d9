#include "http/localize/ranging_localize.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>

#include "http/api_error.hpp"
#include "http/transmitters/transmitter_fields.hpp"
#include "http/validation.hpp"
#include "store/kinds.hpp"
#include "transmitters/refused.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

double option(const json& o, const char* field, double lo, double hi, double fallback) {
    if (!o.contains(field)) return fallback;
    return finite_number(o, field, "options", lo, hi);
}

int int_option(const json& o, const char* field, int lo, int hi, int fallback) {
    if (!o.contains(field)) return fallback;
    const auto& v = o.at(field);
    if (!v.is_number_integer()) throw invalid_field("'options." + std::string(field) + "' must be an integer");
    const auto n = v.get<std::int64_t>();
    if (n < lo || n > hi)
        throw ApiError(422, "out_of_range",
                       "'options." + std::string(field) + "' must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(n);
}

}  // namespace

std::optional<RangingRequest> parse_ranging_request(const std::string& body) {
    // The fingerprint matchers' bodies are the hot path: they never hold these names.
    if (body.find("lateration") == std::string::npos && body.find("proximity") == std::string::npos) return std::nullopt;
    reject_deep(body);
    json j = json::parse(body, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return std::nullopt;  // the full parser words the error
    const auto it = j.find("algorithm");
    if (it == j.end() || !it->is_string()) return std::nullopt;
    const auto& name = it->get_ref<const std::string&>();
    if (name != "trilateration" && name != "multilateration" && name != "proximity") return std::nullopt;
    reject_nul(body);
    only_fields(j, {"algorithm", "scans", "measurements", "options"}, "");
    RangingRequest r;
    r.multilateration = name == "multilateration";
    r.proximity = name == "proximity";
    const bool has_scans = j.contains("scans"), has_means = j.contains("measurements");
    if (has_scans == has_means) throw invalid_field("send exactly one of 'scans' or 'measurements'");
    if (has_scans) {
        r.query = match::Query::from_scans(parse_scans(j.at("scans"), "scans"));
    } else {
        const json& m = j.at("measurements");
        if (!m.is_array() || m.empty()) throw invalid_field("'measurements' must be a non-empty array of {bssid, rss}");
        std::vector<Reading> means;
        for (std::size_t i = 0; i < m.size(); ++i) {
            // "mean" is the fingerprint parser's other spelling of "rss" here.
            json reading = m[i];
            if (reading.is_object() && reading.contains("mean") && !reading.contains("rss")) {
                reading["rss"] = reading["mean"];
                reading.erase("mean");
            }
            means.push_back(parse_reading(reading, "measurements[" + std::to_string(i) + "]"));
        }
        r.query = match::Query::from_means(means);
    }
    if (j.contains("options")) {
        const json& o = j.at("options");
        if (!o.is_object()) throw invalid_field("'options' must be an object");
        if (r.proximity) only_fields(o, {"phone_height"}, "options");  // nothing else is ranged
        only_fields(o, {"cutoff", "vote_slack", "correct", "max_transmitters", "sigma_db", "loss_scale", "max_iterations",
                        "phone_height"},
                    "options");
        auto& t = r.trilateration;
        t.cutoff = option(o, "cutoff", 0.1, 1000.0, t.cutoff);
        t.vote_slack = option(o, "vote_slack", 0.0, 100.0, t.vote_slack);
        if (o.contains("correct")) {
            if (!o.at("correct").is_boolean()) throw invalid_field("'options.correct' must be true or false");
            t.correct = o.at("correct").get<bool>();
        }
        t.max_transmitters = int_option(o, "max_transmitters", 3, 30, t.max_transmitters);
        auto& m = r.multilateration_options;
        m.sigma_db = option(o, "sigma_db", 0.1, 30.0, m.sigma_db);
        m.loss_scale = option(o, "loss_scale", 0.1, 100.0, m.loss_scale);
        m.max_iterations = int_option(o, "max_iterations", 1, 200, m.max_iterations);
        r.phone_height = option(o, "phone_height", -10.0, 100.0, r.phone_height);
    }
    return r;
}

namespace {

// The fields every ranging answer has: where, its floor and building, its room and the POIs
// near it, and its WGS84 position when the floor is georeferenced.
json placed(store::Store& store, PositionViews& views, std::int64_t floor_id, Point at, const char* algorithm) {
    const auto floor = store.get(store::kind("floors"), floor_id);
    json out = {{"x", at.x}, {"y", at.y}, {"floor_id", floor_id}, {"building_id", floor.parent_id.value()}, {"algorithm", algorithm}};
    add_places(out, views.places.of_floor(floor_id).get(), at);
    add_lat_lon(out, views.geo.of_floor(floor_id).get(), at);
    return out;
}

// "proximity": the strongest known transmitter's own position, and how far its model puts
// the phone from it.
std::string proximity_answer(store::Store& store, PositionViews& views, const transmitters::KnownTransmitters& known,
                             const match::Query& query) {
    transmitters::Nearest n;
    try {
        n = transmitters::nearest_transmitter(known, query);
    } catch (const transmitters::Refused& e) {
        throw ApiError(422, e.code, e.what());
    }
    json out = placed(store, views, n.transmitter->floor_id, n.transmitter->tx.at, "proximity");
    out["transmitter"] = {{"id", n.transmitter->id}, {"name", n.transmitter->name}, {"type", n.type}, {"bssid", n.bssid}, {"rss", n.rss}};
    out["range_m"] = n.range_m;
    out["transmitters_heard"] = n.heard;
    return out.dump();
}

}  // namespace

std::string ranging_answer(store::Store& store, transmitters::TransmitterCache& cache, PositionViews& views, bool map_scope,
                           std::int64_t id, const RangingRequest& request) {
    if (request.proximity)
        return proximity_answer(store, views, transmitters::known_transmitters(store, cache, map_scope, id, request.phone_height),
                                request.query);
    transmitters::Ranged ranged;
    try {
        ranged = transmitters::range_scan(transmitters::known_transmitters(store, cache, map_scope, id, request.phone_height), request);
    } catch (const transmitters::Refused& e) {
        throw ApiError(422, e.code, e.what());
    }
    const std::int64_t floor_id = ranged.floor_id;
    const auto* fix = &ranged.fix;
    const std::size_t count = ranged.heard;
    const char* algorithm = request.multilateration ? "multilateration" : "trilateration";
    json out = placed(store, views, floor_id, fix->at, algorithm);
    out["uncertainty"] = {{"semi_major", std::isfinite(fix->uncertainty.semi_major) ? json(fix->uncertainty.semi_major) : json()},
                          {"semi_minor", std::isfinite(fix->uncertainty.semi_minor) ? json(fix->uncertainty.semi_minor) : json()},
                          {"angle_deg", fix->uncertainty.angle_deg}};
    out["transmitters_heard"] = count;
    out["transmitters_used"] = fix->used;
    out["residual"] = fix->rms_residual;
    return out.dump();
}

}  // namespace locus::http
