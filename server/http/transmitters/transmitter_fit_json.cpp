#include "http/transmitters/transmitter_fit_json.hpp"

#include "http/api_error.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

transmitters::FitRequest parse_fit_request(const httplib::Request& req, std::int64_t floor_id) {
    transmitters::FitRequest r;
    r.floor_id = floor_id;
    if (req.has_param("apply")) {
        const auto v = req.get_param_value("apply");
        if (v != "true" && v != "false") throw invalid_query("'apply' must be true or false");
        r.apply = v == "true";
    }
    const json body = req.body.empty() ? json::object() : parse_object(req.body);
    only_fields(body, {"min_rps", "refit_positions", "phone_height", "transmitters"}, "");
    if (body.contains("min_rps")) {
        const auto& v = body.at("min_rps");
        if (!v.is_number_integer() || v.get<std::int64_t>() < 4 || v.get<std::int64_t>() > 100000)
            throw invalid_field("'min_rps' must be an integer in [4, 100000]");
        r.min_rps = static_cast<int>(v.get<std::int64_t>());
    }
    if (body.contains("refit_positions")) {
        if (!body.at("refit_positions").is_boolean()) throw invalid_field("'refit_positions' must be true or false");
        r.refit_positions = body.at("refit_positions").get<bool>();
    }
    if (body.contains("phone_height")) r.phone_height = finite_number(body, "phone_height", "", -10.0, 100.0);
    if (body.contains("transmitters")) {
        const auto& t = body.at("transmitters");
        if (!t.is_array()) throw invalid_field("'transmitters' must be an array of transmitter ids");
        for (const auto& id : t) {
            if (!id.is_number_integer() || id.get<std::int64_t>() <= 0)
                throw invalid_field("'transmitters' must be an array of transmitter ids");
            r.named.insert(id.get<std::int64_t>());
        }
    }
    return r;
}

json fit_json(std::int64_t floor_id, const transmitters::FitResult& result) {
    json fitted = json::array(), skipped = json::array();
    for (const auto& t : result.fitted)
        fitted.push_back({{"id", t.id ? json(*t.id) : json()},
                          {"type", t.type},
                          {"bssid", t.bssid},
                          {"x", t.at.x},
                          {"y", t.at.y},
                          {"position", t.position_fitted ? "fitted" : "known"},
                          {"tx_power", t.model.tx_power},
                          {"path_loss_exponent", t.model.exponent},
                          {"r2", t.r2},
                          {"residual_db", t.residual_db},
                          {"rps", t.rps}});
    for (const auto& s : result.skipped)
        skipped.push_back({{"type", s.type}, {"bssid", s.bssid}, {"rps", s.rps}, {"reason", s.reason}});
    return json{{"floor_id", floor_id},
                {"rps", result.rps},
                {"applied", result.applied},
                {"transmitters", std::move(fitted)},
                {"skipped", std::move(skipped)}};
}

}  // namespace locus::http
