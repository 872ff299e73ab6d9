#include "http/transmitters/transmitter_fit.hpp"

#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <vector>

#include "http/api_error.hpp"
#include "http/app.hpp"
#include "http/transmitters/transmitter_fields.hpp"
#include "http/validation.hpp"
#include "locus/ranging/fit.hpp"
#include "store/kinds.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

struct FitRequest {
    int min_rps = 5;
    bool refit_positions = false;
    double phone_height = 1.2;
    std::set<std::int64_t> named;  // transmitter ids that must be fitted
    bool apply = false;
};

FitRequest parse_fit_request(const httplib::Request& req) {
    FitRequest r;
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

std::string key_of(const std::string& type, const std::string& bssid) { return type + "|" + bssid; }

struct Heard {
    std::string type, bssid;
    std::vector<ranging::Sample> samples;
};

}  // namespace

void install_transmitter_fit(httplib::Server& server, store::Store& store) {
    server.Post(R"(/v1/floors/(\d+)/transmitters/fit)", [&store](const httplib::Request& req, httplib::Response& res) {
        App::respond(req, res, [&] {
            const auto floor_id = parse_id(req.matches[1].str(), "floor");
            const FitRequest request = parse_fit_request(req);
            const store::Record floor = store.get(store::kind("floors"), floor_id);
            const double width = floor.fields.get<double>("width"), height = floor.fields.get<double>("height");

            // Every AP's mean RSS at every surveyed RP of the floor.
            std::map<std::string, Heard> heard;
            std::size_t rp_count = 0;
            const auto radiomaps = store.list(store::kind("radiomaps"), floor_id, 1'000'000, 0);
            for (const auto& rm : radiomaps.items)
                for (const auto& srp : store.rps_of_radiomap(rm.id)) {
                    ++rp_count;
                    for (const auto& m : srp.rp.measurements) {
                        auto& h = heard[key_of(m.type, m.bssid.str())];
                        h.type = m.type;
                        h.bssid = m.bssid.str();
                        h.samples.push_back({srp.rp.at, m.stats.mean});
                    }
                }
            std::map<std::string, store::Record> known;
            for (auto& t : transmitters_of_floor(store, floor_id))
                known.emplace(key_of(t.fields.get<std::string>("type"), t.fields.get<std::string>("bssid")), std::move(t));
            for (std::int64_t id : request.named) {
                bool found = false;
                for (const auto& [key, t] : known) found = found || t.id == id;
                if (!found) throw ApiError(404, "not_found", "transmitter " + std::to_string(id) + " is not on floor " + std::to_string(floor_id));
            }
            // A named transmitter heard too rarely refuses the whole request, naming it.
            for (const auto& [key, t] : known) {
                if (!request.named.count(t.id)) continue;
                const auto it = heard.find(key);
                const std::size_t n = it == heard.end() ? 0 : it->second.samples.size();
                if (n < static_cast<std::size_t>(request.min_rps))
                    throw ApiError(422, "too_few_rps",
                                   "transmitter " + std::to_string(t.id) + " ('" + t.fields.get<std::string>("bssid") + "') is heard at " +
                                       std::to_string(n) + " RP" + (n == 1 ? "" : "s") + " of floor " + std::to_string(floor_id) +
                                       "; a fit needs at least " + std::to_string(request.min_rps));
            }

            ranging::FitOptions options;
            options.area = {0, 0, width, height};
            json fitted = json::array(), skipped = json::array();
            std::vector<store::RowWrite> writes;
            for (const auto& entry : heard) {
                // Named, not a structured binding: clang 14 (the fuzz build) cannot capture
                // one in the lambda below.
                const std::string& key = entry.first;
                const Heard& h = entry.second;
                const auto k = known.find(key);
                const bool is_known = k != known.end();
                if (!request.named.empty() && (!is_known || !request.named.count(k->second.id))) continue;
                auto skip = [&](const char* why) {
                    skipped.push_back({{"type", h.type}, {"bssid", h.bssid}, {"rps", h.samples.size()}, {"reason", why}});
                };
                if (h.samples.size() < static_cast<std::size_t>(request.min_rps)) {
                    skip("too_few_rps");
                    continue;
                }
                const bool fit_position = !is_known || request.refit_positions;
                std::optional<ranging::ModelFit> fit;
                if (fit_position) {
                    fit = ranging::fit_position_and_model(h.samples, options);
                } else {
                    const auto& f = k->second.fields;
                    const auto& z = f.values.at("z");
                    const double dz = std::holds_alternative<double>(z) ? std::get<double>(z) - request.phone_height : 0.0;
                    fit = ranging::fit_model(h.samples, {f.get<double>("x"), f.get<double>("y")}, dz, options);
                }
                if (!fit) {
                    skip("degenerate");  // every RP at one distance
                    continue;
                }
                if (fit->model.tx_power < -120 || fit->model.tx_power > 30) {
                    skip("implausible_tx_power");
                    continue;
                }
                json item = {{"id", is_known ? json(k->second.id) : json()},
                             {"type", h.type},
                             {"bssid", h.bssid},
                             {"x", fit->at.x},
                             {"y", fit->at.y},
                             {"position", fit_position ? "fitted" : "known"},
                             {"tx_power", fit->model.tx_power},
                             {"path_loss_exponent", fit->model.exponent},
                             {"r2", fit->r2},
                             {"residual_db", fit->residual_db},
                             {"rps", fit->samples}};
                fitted.push_back(item);
                store::Fields f{{"tx_power", fit->model.tx_power}, {"path_loss_exponent", fit->model.exponent}};
                if (fit_position) {
                    f.values["x"] = fit->at.x;
                    f.values["y"] = fit->at.y;
                }
                if (!is_known) {
                    f.values["type"] = h.type;
                    f.values["bssid"] = h.bssid;
                    f.values["name"] = std::string("fitted from the survey");
                }
                writes.push_back({is_known ? std::optional(k->second.id) : std::nullopt, std::move(f)});
            }
            if (request.apply) {
                // One transaction: a refused row (say a transmitter created meanwhile with a
                // fitted one's bssid) leaves the floor's transmitters as they were.
                const auto rows = store.write_rows(store::kind("transmitters"), floor_id, writes);
                for (std::size_t i = 0; i < rows.size(); ++i) fitted[i]["id"] = rows[i].id;
            }
            return std::pair{200, json{{"floor_id", floor_id},
                                       {"rps", rp_count},
                                       {"applied", request.apply},
                                       {"transmitters", fitted},
                                       {"skipped", skipped}}};
        });
    });
}

}  // namespace locus::http
