#include "http/radiomaps/radiomap_settings.hpp"

#include "http/localize/localize_request.hpp"

namespace locus::http {

using nlohmann::json;

json settings_json(const match::Setting& s) {
    const auto& o = s.options;
    // Every option a setting fixes, so the stored text says all it means whatever later
    // releases choose as built-in defaults ("near" and "candidates" are per request).
    json options{{"k", o.k},
                 {"bayes_k", o.bayes_k},
                 {"tolerance", o.tolerance},
                 {"gamma", o.gamma},
                 {"representation", match::to_string(o.representation)},
                 {"distance", match::to_string(o.distance)},
                 {"sigma_floor", o.sigma_floor},
                 {"outlier_sigmas", o.outlier_sigmas},
                 {"estimate", match::to_string(o.estimate)},
                 {"temperature", o.temperature},
                 {"offset_sigma", o.offset_sigma},
                 {"floor_temperature", o.floor_temperature},
                 {"floor_knn", o.floor_knn},
                 {"floor_knn_weight", o.floor_knn_weight},
                 {"floor_knn_position", o.floor_knn_position},
                 {"floor_aps", o.floor_aps},
                 {"floor_ap_weight", o.floor_ap_weight}};
    return json{{"algorithm", match::to_string(s.algorithm)}, {"options", std::move(options)}};
}

match::Setting settings_of_text(const std::string& text) {
    match::Setting s;
    if (text.empty()) return s;
    try {
        const auto j = json::parse(text);
        const auto a = match::parse_algorithm(j.at("algorithm").get<std::string>());
        if (!a) return {};
        s.algorithm = *a;
        s.options = parse_options(j.at("options"), {}, "settings.options");
    } catch (const std::exception&) {
        return {};
    }
    return s;
}

json tune_json(const match::TuneReport& report, double seconds) {
    json rows = json::array();
    for (const auto& r : report.rows)
        rows.push_back(json{{"name", r.name},
                            {"settings", settings_json(r.setting)},
                            {"mean_error_m", r.mean_error_m},
                            {"mean_horizontal_error_m", r.mean_horizontal_m},
                            {"floor_hit_rate", r.floor_hit_rate},
                            {"building_hit_rate", r.building_hit_rate},
                            {"unanswered", r.unanswered}});
    return json{{"method", "k-fold cross-validation over the radio map's RPs, each RP's stored means as the scan"},
                {"folds", report.folds},
                {"rps", report.rps},
                {"queries", report.queries},
                {"subsampled", report.subsampled},
                {"seconds", seconds},
                {"chosen", report.best},
                {"candidates", std::move(rows)}};
}

tuning::SettingsText settings_text() {
    return {settings_of_text, [](const match::Setting& s) { return settings_json(s).dump(); },
            [](const match::TuneReport& report, double seconds) { return tune_json(report, seconds).dump(); }};
}

void add_settings(json& radiomap, const std::optional<store::RadiomapSettings>& stored) {
    json settings = settings_json(stored ? settings_of_text(stored->settings) : match::Setting{});
    settings["source"] = stored ? "tuned" : "built-in";
    if (stored) settings["updated_at"] = stored->updated_at;
    radiomap["settings"] = std::move(settings);
    if (!stored) return;
    try {
        radiomap["tune"] = json::parse(stored->tune);
    } catch (const json::exception&) {
        // A damaged row: the settings above already fell back; show no table.
    }
}

}  // namespace locus::http
