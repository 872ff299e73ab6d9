#include "localize/request.hpp"

#include "http/api_error.hpp"
#include "http/validation.hpp"
#include "locus/match/localize.hpp"

namespace locus::localize {

using nlohmann::json;
using http::ApiError;
using http::invalid_field;

namespace {

template <typename T, typename Parse>
T parse_enum(const json& options, const char* field, Parse parse, T fallback) {
    const auto s = http::optional_string(options, field, "options", 32);
    if (!s) return fallback;
    const auto v = parse(*s);
    if (!v) throw invalid_field("'options." + std::string(field) + "' has no value \"" + *s + "\"");
    return *v;
}

int bounded_int(const json& options, const char* field, int lo, int hi, int fallback) {
    if (!options.contains(field)) return fallback;
    const auto& v = options.at(field);
    if (!v.is_number_integer()) throw invalid_field("'options." + std::string(field) + "' must be an integer");
    const auto n = v.get<std::int64_t>();
    if (n < lo || n > hi)
        throw ApiError(422, "out_of_range",
                       "'options." + std::string(field) + "' must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(n);
}

double bounded_number(const json& options, const char* field, double lo, double hi, double fallback) {
    if (!options.contains(field)) return fallback;
    return http::finite_number(options, field, "options", lo, hi);
}

match::Options parse_options(const json& body) {
    match::Options o;
    if (!body.contains("options")) return o;
    const json& j = body.at("options");
    if (!j.is_object()) throw invalid_field("'options' must be an object");
    static const std::initializer_list<const char*> known = {"k", "tolerance", "gamma", "near", "representation",
                                                              "distance", "sigma_floor", "estimate", "candidates",
                                                              "temperature", "offset_sigma"};
    for (const auto& [key, value] : j.items()) {
        bool ok = false;
        for (const char* k : known) ok = ok || key == k;
        if (!ok) throw invalid_field("unknown option '" + key + "'");
    }
    o.k = bounded_int(j, "k", 1, 100, o.k);
    o.candidates = bounded_int(j, "candidates", 1, 100, o.candidates);
    o.tolerance = bounded_number(j, "tolerance", 0.0, 10.0, o.tolerance);
    o.gamma = bounded_number(j, "gamma", 0.0, 1000.0, o.gamma);
    o.sigma_floor = bounded_number(j, "sigma_floor", 0.1, 60.0, o.sigma_floor);
    o.temperature = bounded_number(j, "temperature", 0.01, 1000.0, o.temperature);
    o.offset_sigma = bounded_number(j, "offset_sigma", 0.0, 60.0, o.offset_sigma);
    o.representation = parse_enum(j, "representation", match::parse_representation, o.representation);
    o.distance = parse_enum(j, "distance", match::parse_distance, o.distance);
    o.estimate = parse_enum(j, "estimate", match::parse_bayes_estimate, o.estimate);
    if (j.contains("near")) {
        const json& n = j.at("near");
        if (!n.is_object()) throw invalid_field("'options.near' must be an object {x, y, radius}");
        match::Near near;
        near.at.x = http::finite_number(n, "x", "options.near");
        near.at.y = http::finite_number(n, "y", "options.near");
        near.radius = http::finite_number(n, "radius", "options.near", 0.0);
        if (!(near.radius > 0.0)) throw ApiError(422, "out_of_range", "'options.near.radius' must be greater than 0");
        o.near = near;
    }
    return o;
}

std::vector<Reading> parse_means(const json& arr) {
    if (!arr.is_array() || arr.empty()) throw invalid_field("'measurements' must be a non-empty array of {bssid, rss}");
    std::vector<Reading> out;
    for (std::size_t i = 0; i < arr.size(); ++i) {
        const std::string where = "measurements[" + std::to_string(i) + "]";
        json m = arr[i];
        // A live scan's per-AP mean may be sent as "rss" or, like a stored measurement, "mean".
        if (m.is_object() && m.contains("mean") && !m.contains("rss")) {
            m["rss"] = m.at("mean");
            m.erase("mean");
        }
        out.push_back(http::parse_reading(m, where));
    }
    return out;
}

}  // namespace

LocalizeRequest parse_localize_request(const std::string& body_text) {
    const json body = http::parse_object(body_text);
    for (const auto& [key, value] : body.items())
        if (key != "algorithm" && key != "scans" && key != "measurements" && key != "options")
            throw invalid_field("unknown field '" + key + "'");
    LocalizeRequest r;
    if (const auto name = http::optional_string(body, "algorithm", "", 32)) {
        const auto a = match::parse_algorithm(*name);
        if (!a) throw invalid_field("unknown algorithm \"" + *name + "\" (bsb, nn, bsbnn, knn, wknn, bayes)");
        r.algorithm = *a;
    }
    const bool has_scans = body.contains("scans"), has_means = body.contains("measurements");
    if (has_scans == has_means) throw invalid_field("send exactly one of 'scans' or 'measurements'");
    r.query = has_scans ? match::Query::from_scans(http::parse_scans(body.at("scans"), "scans"))
                        : match::Query::from_means(parse_means(body.at("measurements")));
    if (r.query.aps.empty()) throw invalid_field("the scan holds no reading");
    r.options = parse_options(body);
    return r;
}

json answer(const Snapshot& snapshot, const LocalizeRequest& request) {
    const auto result = match::localize(snapshot.index, request.query, request.algorithm, request.options);
    if (!result)
        throw ApiError(422, "no_match",
                       "no reference point shares an access point with the scan" +
                           std::string(request.options.near ? " within the 'near' subarea" : ""));
    json room = nullptr;
    if (auto it = snapshot.rooms_by_floor.find(result->floor_id); it != snapshot.rooms_by_floor.end()) {
        for (const auto& r : it->second)
            if (r.contains(result->at)) {
                room = {{"id", r.id}, {"name", r.name}};
                break;
            }
    }
    json candidates = json::array();
    for (const auto& c : result->candidates)
        candidates.push_back({{"rp_id", c.rp_id},
                              {"x", c.at.x},
                              {"y", c.at.y},
                              {"score", c.score},
                              {"floor_id", c.floor_id},
                              {"building_id", c.building_id},
                              {"matched_aps", c.matched_aps}});
    return {{"x", result->at.x},
            {"y", result->at.y},
            {"floor_id", result->floor_id},
            {"building_id", result->building_id},
            {"room", room},
            {"rps", result->rp_ids},
            {"score", result->score},
            {"matched_aps", result->matched_aps},
            {"algorithm", result->algorithm},
            {"candidates", candidates}};
}

}  // namespace locus::localize
