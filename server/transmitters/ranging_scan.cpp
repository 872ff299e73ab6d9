#include "transmitters/ranging_scan.hpp"

#include <charconv>
#include <cmath>
#include <system_error>
#include <variant>
#include <vector>

#include "store/kinds.hpp"
#include "transmitters/refused.hpp"

namespace locus::transmitters {

namespace {

void add_floor(TransmitterCache& cache, std::int64_t floor_id, double phone_height, std::map<std::string, KnownTransmitter>& out) {
    const auto txs = cache.of_floor(floor_id);
    for (const auto& r : *txs) {
        const auto& f = r.fields;
        KnownTransmitter k;
        k.floor_id = floor_id;
        k.tx.at = {f.get<double>("x"), f.get<double>("y")};
        const auto& z = f.values.at("z");
        k.tx.dz = std::holds_alternative<double>(z) ? std::get<double>(z) - phone_height : 0.0;
        k.tx.model = {f.get<double>("tx_power"), f.get<double>("path_loss_exponent")};
        k.id = r.id;
        if (const auto name = f.values.find("name"); name != f.values.end() && std::holds_alternative<std::string>(name->second))
            k.name = std::get<std::string>(name->second);
        out.emplace(transmitter_key(f.get<std::string>("type"), f.get<std::string>("bssid")), k);
    }
}

std::vector<std::int64_t> floors_of_map(store::Store& store, std::int64_t map_id) {
    std::vector<std::int64_t> floors;
    store.get(store::kind("maps"), map_id);  // NotFound for an unknown map
    const auto buildings = store.list(store::kind("buildings"), map_id, 1'000'000, 0);
    for (const auto& b : buildings.items)
        for (const auto& f : store.list(store::kind("floors"), b.id, 1'000'000, 0).items) floors.push_back(f.id);
    return floors;
}

// A number for a message: the shortest text that reads back as v ("null" when not finite).
std::string number(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[32];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
    return ec == std::errc{} ? std::string(buf, end) : std::to_string(v);
}

}  // namespace

std::string transmitter_key(std::string_view type, std::string_view bssid) {
    std::string k(type);
    k += '|';
    k += bssid;
    return k;
}

KnownTransmitters known_transmitters(store::Store& store, TransmitterCache& cache, bool map_scope, std::int64_t id, double phone_height) {
    KnownTransmitters known;
    known.map_scope = map_scope;
    if (map_scope) {
        for (std::int64_t floor : floors_of_map(store, id)) add_floor(cache, floor, phone_height, known.by_key);
    } else {
        const auto radiomap = store.get(store::kind("radiomaps"), id);
        add_floor(cache, radiomap.parent_id.value(), phone_height, known.by_key);
    }
    return known;
}

Ranged range_scan(const KnownTransmitters& known, const RangingRequest& request) {
    const bool map_scope = known.map_scope;
    // The heard transmitters by floor; the floor that hears most is where the phone is.
    std::map<std::int64_t, std::vector<ranging::Heard>> by_floor;
    for (const auto& ap : request.query.aps) {
        const auto k = known.by_key.find(transmitter_key(ap.type, ap.bssid));
        if (k != known.by_key.end()) by_floor[k->second.floor_id].push_back({k->second.tx, ap.rss});
    }
    std::int64_t floor_id = 0;
    const std::vector<ranging::Heard>* heard = nullptr;
    for (const auto& [f, h] : by_floor)
        if (!heard || h.size() > heard->size()) {
            floor_id = f;
            heard = &h;
        }
    const std::size_t count = heard ? heard->size() : 0;
    const char* algorithm = request.multilateration ? "multilateration" : "trilateration";
    if (count < 3)
        throw Refused("too_few_transmitters", "the scan hears " + std::to_string(count) + " known transmitter" + (count == 1 ? "" : "s") +
                                                  (map_scope ? " on any floor of the map" : " of the radio map's floor") + "; " +
                                                  algorithm + " needs at least 3");
    const auto fix = request.multilateration ? ranging::multilaterate(*heard, request.multilateration_options)
                                             : ranging::trilaterate(*heard, request.trilateration);
    if (!fix)
        throw Refused("no_fix", std::string(algorithm) + " found no position from the " + std::to_string(count) +
                                    " transmitters heard (fewer than 3 within the cutoff of " + number(request.trilateration.cutoff) +
                                    " m, or all in a line)");
    return {floor_id, *fix, count};
}

Nearest nearest_transmitter(const KnownTransmitters& known, const match::Query& query) {
    Nearest out;
    for (const auto& ap : query.aps) {
        const auto k = known.by_key.find(transmitter_key(ap.type, ap.bssid));
        if (k == known.by_key.end()) continue;
        ++out.heard;
        // The strongest reading; at equal RSS the first in the query's (type, bssid) order.
        if (out.transmitter && !(ap.rss > out.rss)) continue;
        out.transmitter = &k->second;
        out.type = ap.type;
        out.bssid = ap.bssid;
        out.rss = ap.rss;
    }
    if (!out.transmitter)
        throw Refused("no_known_transmitter", std::string("the scan hears no known transmitter") +
                                                  (known.map_scope ? " on any floor of the map" : " of the radio map's floor"));
    out.range_m = ranging::horizontal(ranging::range_of(out.transmitter->tx.model, out.rss), out.transmitter->tx.dz);
    return out;
}

}  // namespace locus::transmitters
