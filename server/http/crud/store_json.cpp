#include "http/crud/store_json.hpp"

#include <initializer_list>
#include <iterator>
#include <string>
#include <string_view>

#include "http/api_error.hpp"
#include "http/transmitters/transmitter_fields.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

json value_json(const store::Value& v) {
    return std::visit(
        [](const auto& x) -> json {
            if constexpr (std::is_same_v<std::decay_t<decltype(x)>, std::monostate>) return nullptr;
            else return x;
        },
        v);
}

json rects_json(const std::vector<Rect>& rects) {
    json out = json::array();
    for (const auto& r : rects) out.push_back({{"xmin", r.xmin}, {"ymin", r.ymin}, {"xmax", r.xmax}, {"ymax", r.ymax}});
    return out;
}

json measurements_json(const std::vector<Measurement>& ms) {
    json out = json::array();
    for (const auto& m : ms) out.push_back(measurement_json(m));
    return out;
}

// The object without the keys that hold the next level down, so that the level itself is
// validated as its own create route would.
json level_of(const json& j, std::initializer_list<std::string_view> children, const std::string& where) {
    if (!j.is_object()) throw invalid_field("'" + where + "' must be an object");
    json out = j;
    for (auto c : children) out.erase(std::string(c));
    return out;
}

const json& list_of(const json& j, const char* key, const std::string& where) {
    static const json empty = json::array();
    const auto it = j.find(key);
    if (it == j.end()) return empty;
    if (!it->is_array()) throw invalid_field("'" + where + "." + key + "' must be an array");
    return *it;
}

store::Fields fields_at(const store::Kind& kind, const json& level, const std::string& where) {
    try {
        return validated_fields(kind, level, true);
    } catch (const ApiError& e) {
        throw ApiError(e.status, e.code, where + ": " + e.what());
    }
}

// The members of a group (store::Field::group) leave the answer as columns and come back as
// the group's object, or as null unless every one of them is set.
void fold_groups(const store::Kind& kind, json& out) {
    for (const auto& f : kind.fields) {
        if (f.group.empty()) continue;
        json member = nullptr;
        if (const auto it = out.find(std::string(f.name)); it != out.end()) {
            member = std::move(*it);
            out.erase(it);
        }
        json& group = out.emplace(std::string(f.group), json::object()).first.value();
        if (group.is_object() && !member.is_null()) group[std::string(f.key)] = std::move(member);
        else group = nullptr;
    }
}

}  // namespace

json record_json(const store::Kind& kind, const store::Record& record) {
    json out = json::object();
    out["id"] = record.id;
    if (!kind.parent_column.empty()) out[std::string(kind.parent_column)] = record.parent_id.value_or(0);
    for (const auto& [name, value] : record.fields.values) out[name] = value_json(value);
    fold_groups(kind, out);
    if (kind.has_rects) out["rects"] = rects_json(record.fields.rects.value_or(std::vector<Rect>{}));
    return out;
}

json page_json(const store::Kind& kind, const store::RecordPage& page) {
    json items = json::array();
    for (const auto& r : page.items) items.push_back(record_json(kind, r));
    return {{"items", items}, {"total", page.total}, {"limit", page.limit}, {"offset", page.offset}};
}

json measurement_json(const Measurement& m) {
    return {{"type", m.type}, {"bssid", m.bssid}, {"mean", m.stats.mean}, {"variance", m.stats.variance},
            {"count", m.stats.count}};
}

json rp_json(const store::RpRecord& rp) {
    json out = record_json(store::kind("rps"), rp.rp);
    out["measurements"] = measurements_json(rp.measurements);
    return out;
}

json export_rp_json(const store::RpDocument& rp) {
    return {{"name", rp.name}, {"x", rp.at.x}, {"y", rp.at.y}, {"scans", rp.scans}, {"measurements", measurements_json(rp.measurements)}};
}

json export_json(const store::RadioMapExport& doc) {
    json out = export_json_without_rps(doc.radiomap, doc.transmitters);
    json& rps = out["rps"];
    for (const auto& rp : doc.rps) rps.push_back(export_rp_json(rp));
    return out;
}

json export_json_without_rps(const store::Record& radiomap, const std::vector<store::Record>& floor_transmitters) {
    // The floor's transmitters without their ids, as a create body: a calibrated model moves
    // with the survey (ranging and generate need them on the target floor).
    json transmitters = json::array();
    for (const auto& t : floor_transmitters) {
        json item = record_json(store::kind("transmitters"), t);
        item.erase("id");
        item.erase("floor_id");
        for (auto it = item.begin(); it != item.end();) it = it->is_null() ? item.erase(it) : std::next(it);  // absent = unset
        transmitters.push_back(std::move(item));
    }
    const auto& f = radiomap.fields.values;
    return {{"format", "locus-radiomap/1"},
            {"name", value_json(f.at("name"))},
            {"description", value_json(f.at("description"))},
            {"floor_id", radiomap.parent_id.value_or(0)},
            {"rps", json::array()},
            {"transmitters", transmitters}};
}

json imported_json(const store::ImportedRadioMap& imported) {
    json out = record_json(store::kind("radiomaps"), imported.radiomap);
    out["rp_count"] = imported.rp_count;
    out["measurement_count"] = imported.measurement_count;
    out["transmitters_created"] = imported.transmitters_created;
    out["transmitters_kept"] = imported.transmitters_kept;
    return out;
}

store::MapBundle parse_map_bundle(const json& bundle) {
    if (!bundle.is_object()) throw invalid_field("a map bundle must be an object {map, buildings}");
    only_fields(bundle, {"map", "buildings"}, "");
    store::MapBundle out;
    out.fields = fields_at(store::kind("maps"), level_of(bundle.value("map", json::object()), {}, "map"), "map");
    const auto& buildings = list_of(bundle, "buildings", "");
    for (std::size_t i = 0; i < buildings.size(); ++i) {
        const std::string bw = "buildings[" + std::to_string(i) + "]";
        store::BuildingBundle b;
        b.fields = fields_at(store::kind("buildings"), level_of(buildings[i], {"floors"}, bw), bw);
        const auto& floors = list_of(buildings[i], "floors", bw);
        for (std::size_t j = 0; j < floors.size(); ++j) {
            const std::string fw = bw + ".floors[" + std::to_string(j) + "]";
            const json& fj = floors[j];
            store::FloorBundle f;
            // A floor's "plan" is read by parse_bundle_plans (bundle_plans.hpp).
            f.fields = fields_at(store::kind("floors"), level_of(fj, {"rooms", "pois", "radiomaps", "plan"}, fw), fw);
            const auto& rooms = list_of(fj, "rooms", fw);
            for (std::size_t k = 0; k < rooms.size(); ++k)
                f.rooms.push_back(fields_at(store::kind("rooms"), level_of(rooms[k], {}, fw + ".rooms[" + std::to_string(k) + "]"),
                                            fw + ".rooms[" + std::to_string(k) + "]"));
            const auto& pois = list_of(fj, "pois", fw);
            for (std::size_t k = 0; k < pois.size(); ++k)
                f.pois.push_back(fields_at(store::kind("pois"), level_of(pois[k], {}, fw + ".pois[" + std::to_string(k) + "]"),
                                           fw + ".pois[" + std::to_string(k) + "]"));
            const auto& radiomaps = list_of(fj, "radiomaps", fw);
            for (std::size_t k = 0; k < radiomaps.size(); ++k) {
                const std::string rw = fw + ".radiomaps[" + std::to_string(k) + "]";
                try {
                    f.radiomaps.push_back(parse_radiomap_document(radiomaps[k]));
                    const store::Record floor{0, std::nullopt, f.fields};
                    const auto& txs = f.radiomaps.back().transmitters;
                    for (std::size_t t = 0; t < txs.size(); ++t) try {
                            check_on_floor(floor, txs[t].get<double>("x"), txs[t].get<double>("y"));
                        } catch (const ApiError& e) {
                            throw ApiError(e.status, e.code, "transmitters[" + std::to_string(t) + "]: " + e.what());
                        }
                } catch (const ApiError& e) {
                    throw ApiError(e.status, e.code, rw + ": " + e.what());
                }
            }
            b.floors.push_back(std::move(f));
        }
        out.buildings.push_back(std::move(b));
    }
    return out;
}

}  // namespace locus::http
