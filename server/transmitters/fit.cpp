#include "transmitters/fit.hpp"

#include <map>
#include <utility>
#include <variant>

#include "locus/ranging/fit.hpp"
#include "store/kinds.hpp"
#include "transmitters/floor_transmitters.hpp"
#include "transmitters/refused.hpp"

namespace locus::transmitters {

namespace {

std::string key_of(const std::string& type, const std::string& bssid) { return type + "|" + bssid; }

struct Heard {
    std::string type, bssid;
    std::vector<ranging::Sample> samples;
};

// Every AP's mean RSS at every surveyed RP of the floor, by key_of, and the RPs counted.
std::map<std::string, Heard> heard_on_floor(store::Store& store, std::int64_t floor_id, std::size_t& rp_count) {
    std::map<std::string, Heard> heard;
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
    return heard;
}

// Every named transmitter is on the floor and heard at enough RPs, else the whole request is
// refused, naming it.
void check_named(const FitRequest& request, const std::map<std::string, store::Record>& known,
                 const std::map<std::string, Heard>& heard) {
    for (std::int64_t id : request.named) {
        bool found = false;
        for (const auto& [key, t] : known) found = found || t.id == id;
        if (!found)
            throw store::NotFound("transmitter " + std::to_string(id) + " is not on floor " + std::to_string(request.floor_id));
    }
    for (const auto& [key, t] : known) {
        if (!request.named.count(t.id)) continue;
        const auto it = heard.find(key);
        const std::size_t n = it == heard.end() ? 0 : it->second.samples.size();
        if (n < static_cast<std::size_t>(request.min_rps))
            throw Refused("too_few_rps", "transmitter " + std::to_string(t.id) + " ('" + t.fields.get<std::string>("bssid") +
                                             "') is heard at " + std::to_string(n) + " RP" + (n == 1 ? "" : "s") + " of floor " +
                                             std::to_string(request.floor_id) + "; a fit needs at least " +
                                             std::to_string(request.min_rps));
    }
}

// One AP's fit, or why it has none.
std::optional<ranging::ModelFit> fit_one(const Heard& h, const store::Record* known, bool fit_position,
                                         const FitRequest& request, const ranging::FitOptions& options, const char*& why) {
    if (h.samples.size() < static_cast<std::size_t>(request.min_rps)) {
        why = "too_few_rps";
        return std::nullopt;
    }
    std::optional<ranging::ModelFit> fit;
    if (fit_position) {
        fit = ranging::fit_position_and_model(h.samples, options);
    } else {
        const auto& f = known->fields;
        const auto& z = f.values.at("z");
        const double dz = std::holds_alternative<double>(z) ? std::get<double>(z) - request.phone_height : 0.0;
        fit = ranging::fit_model(h.samples, {f.get<double>("x"), f.get<double>("y")}, dz, options);
    }
    if (!fit) {
        why = "degenerate";  // every RP at one distance
        return std::nullopt;
    }
    if (fit->model.tx_power < -120 || fit->model.tx_power > 30) {
        why = "implausible_tx_power";
        return std::nullopt;
    }
    return fit;
}

// The row a fit writes: the model, the position when fitted, and a new transmitter's identity.
store::RowWrite row_of(const FittedTransmitter& t) {
    store::Fields f{{"tx_power", t.model.tx_power}, {"path_loss_exponent", t.model.exponent}};
    if (t.position_fitted) {
        f.values["x"] = t.at.x;
        f.values["y"] = t.at.y;
    }
    if (!t.id) {
        f.values["type"] = t.type;
        f.values["bssid"] = t.bssid;
        f.values["name"] = std::string("fitted from the survey");
    }
    return {t.id, std::move(f)};
}

}  // namespace

FitResult fit_transmitters(store::Store& store, const FitRequest& request) {
    const store::Record floor = store.get(store::kind("floors"), request.floor_id);
    const double width = floor.fields.get<double>("width"), height = floor.fields.get<double>("height");
    FitResult result;
    const auto heard = heard_on_floor(store, request.floor_id, result.rps);
    std::map<std::string, store::Record> known;
    for (auto& t : transmitters_of_floor(store, request.floor_id))
        known.emplace(key_of(t.fields.get<std::string>("type"), t.fields.get<std::string>("bssid")), std::move(t));
    check_named(request, known, heard);

    ranging::FitOptions options;
    options.area = {0, 0, width, height};
    std::vector<store::RowWrite> writes;
    for (const auto& [key, h] : heard) {
        const auto k = known.find(key);
        const store::Record* is_known = k == known.end() ? nullptr : &k->second;
        if (!request.named.empty() && (!is_known || !request.named.count(is_known->id))) continue;
        const bool fit_position = !is_known || request.refit_positions;
        const char* why = "";
        const auto fit = fit_one(h, is_known, fit_position, request, options, why);
        if (!fit) {
            result.skipped.push_back({h.type, h.bssid, h.samples.size(), why});
            continue;
        }
        FittedTransmitter t;
        if (is_known) t.id = is_known->id;
        t.type = h.type;
        t.bssid = h.bssid;
        t.at = fit->at;
        t.position_fitted = fit_position;
        t.model = fit->model;
        t.r2 = fit->r2;
        t.residual_db = fit->residual_db;
        t.rps = fit->samples;
        writes.push_back(row_of(t));
        result.fitted.push_back(std::move(t));
    }
    if (request.apply) {
        // One transaction: a refused row (say a transmitter created meanwhile with a fitted
        // one's bssid) leaves the floor's transmitters as they were.
        const auto rows = store.write_rows(store::kind("transmitters"), request.floor_id, writes);
        for (std::size_t i = 0; i < rows.size(); ++i) result.fitted[i].id = rows[i].id;
    }
    result.applied = request.apply;
    return result;
}

}  // namespace locus::transmitters
