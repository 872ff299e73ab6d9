#include "http/radiomaps/tuning_json.hpp"

#include "http/api_error.hpp"
#include "http/radiomaps/radiomap_settings.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

match::TuneLimits parse_quality_query(const httplib::Request& req) {
    match::TuneLimits limits;
    if (req.has_param("folds")) limits.folds = static_cast<int>(parse_query_integer(req.get_param_value("folds"), "folds", 2, 50));
    if (req.has_param("max_queries"))
        limits.max_queries = static_cast<std::size_t>(parse_query_integer(req.get_param_value("max_queries"), "max_queries", 10, 5000));
    return limits;
}

match::TuneLimits parse_tune_body(const std::string& body) {
    match::TuneLimits limits;
    if (body.empty()) return limits;
    const json j = parse_object(body);
    only_fields(j, {"folds", "max_queries"}, "body");
    const auto integer = [&](const char* field, std::int64_t lo, std::int64_t hi, std::int64_t fallback) {
        if (!j.contains(field)) return fallback;
        const auto& v = j.at(field);
        if (!v.is_number_integer()) throw invalid_field("'" + std::string(field) + "' must be an integer");
        const auto n = v.get<std::int64_t>();
        if (n < lo || n > hi)
            throw ApiError(422, "out_of_range",
                           "'" + std::string(field) + "' must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return n;
    };
    limits.folds = static_cast<int>(integer("folds", 2, 50, limits.folds));
    limits.max_queries = static_cast<std::size_t>(integer("max_queries", 10, 5000, static_cast<std::int64_t>(limits.max_queries)));
    return limits;
}

json quality_json(std::int64_t radiomap_id, const tuning::Quality& quality) {
    const auto& report = quality.report;
    json items = json::array();
    double sum = 0;
    for (const auto& q : report.rps) {
        const auto& r = quality.rps[q.rp];
        json j = {{"id", r.rp.id}, {"name", r.rp.name}, {"floor_id", r.floor_id}, {"x", r.rp.at.x}, {"y", r.rp.at.y},
                  {"error_m", nullptr}, {"horizontal_m", nullptr}, {"floor_ok", q.floor_ok}};
        if (q.error_m) {
            j["error_m"] = *q.error_m;
            sum += *q.error_m;
        }
        if (q.horizontal_m) j["horizontal_m"] = *q.horizontal_m;
        items.push_back(std::move(j));
    }
    json out{{"radiomap_id", radiomap_id}, {"settings", settings_json(quality.setting)}, {"folds", report.folds},
             {"queries", report.queries}, {"subsampled", report.subsampled},
             {"mean_error_m", sum / static_cast<double>(report.queries)}, {"rps", std::move(items)}};
    out["settings"]["source"] = quality.tuned ? "tuned" : "built-in";
    return out;
}

json tuned_json(std::int64_t radiomap_id, const tuning::Tuned& tuned) {
    const auto& best = tuned.report.rows[tuned.report.best];
    json out{{"radiomap_id", radiomap_id}, {"settings", settings_json(best.setting)}, {"tune", tune_json(tuned.report, tuned.seconds)}};
    out["settings"]["source"] = "tuned";
    out["settings"]["updated_at"] = tuned.written.updated_at;
    return out;
}

}  // namespace locus::http
