#include "http/transmitters/transmitter_fields.hpp"

#include <charconv>
#include <string>

#include "http/api_error.hpp"
#include "http/validation.hpp"
#include "locus/ranging/beacon_id.hpp"
#include "store/kinds.hpp"
#include "store/store.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

std::string shortest(double v) {
    char buf[32];
    const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
    return std::string(buf, end);
}

std::string required_string(const json& j, const char* field, const std::string& where) {
    const auto s = optional_string(j, field, where, 64);
    if (!s) throw invalid_field("missing field '" + where + "." + field + "'");
    return *s;
}

std::int64_t uint16_field(const json& j, const char* field, const std::string& where) {
    const auto it = j.find(field);
    const std::string name = where + "." + field;
    if (it == j.end()) throw invalid_field("missing field '" + name + "'");
    if (!it->is_number_integer()) throw invalid_field("'" + name + "' must be an integer");
    const auto v = it->get<std::int64_t>();
    if (v < 0 || v > 65535) throw ApiError(422, "out_of_range", "'" + name + "' must be in [0, 65535]");
    return v;
}

// An iBeacon or Eddystone beacon by its parts, as ranging::ibeacon_id and eddystone_id name it.
std::string ibeacon_id(const json& j) {
    if (!j.is_object()) throw invalid_field("'ibeacon' must be an object {uuid, major, minor}");
    only_fields(j, {"uuid", "major", "minor"}, "ibeacon");
    const std::string uuid = required_string(j, "uuid", "ibeacon");
    const auto major = uint16_field(j, "major", "ibeacon"), minor = uint16_field(j, "minor", "ibeacon");
    const auto id = ranging::ibeacon_id(uuid, major, minor);
    if (!id) throw invalid_field("'ibeacon.uuid' must be a UUID (32 hexadecimal digits, dashes allowed)");
    return *id;
}

std::string eddystone_id(const json& j) {
    if (!j.is_object()) throw invalid_field("'eddystone' must be an object {namespace, instance}");
    only_fields(j, {"namespace", "instance"}, "eddystone");
    const std::string ns = required_string(j, "namespace", "eddystone");
    const std::string instance = required_string(j, "instance", "eddystone");
    if (!ranging::eddystone_id(ns, "000000000000")) throw invalid_field("'eddystone.namespace' must be 20 hexadecimal digits");
    const auto id = ranging::eddystone_id(ns, instance);
    if (!id) throw invalid_field("'eddystone.instance' must be 12 hexadecimal digits");
    return *id;
}

}  // namespace

store::Fields transmitter_fields(const json& body, bool create) {
    json plain = body;
    std::optional<std::string> beacon;
    for (const char* form : {"ibeacon", "eddystone"}) {
        const auto it = body.find(form);
        if (it == body.end()) continue;
        if (beacon || body.contains("bssid"))
            throw invalid_field("give one of 'bssid', 'ibeacon' and 'eddystone', not several");
        beacon = std::string(form) == "ibeacon" ? ibeacon_id(*it) : eddystone_id(*it);
        plain.erase(form);
    }
    if (beacon) {
        if (body.contains("type") && body.at("type") != "ble")
            throw invalid_field("'type' must be \"ble\" for an iBeacon or Eddystone beacon");
        plain["bssid"] = *beacon;
        plain["type"] = "ble";
    }
    store::Fields out = validated_fields(store::kind("transmitters"), plain, create);
    if (out.has("type")) {
        if (const char* problem = type_problem(out.get<std::string>("type"))) throw invalid_field(std::string("'type' ") + problem);
    }
    if (out.has("bssid")) {
        const auto& raw = out.get<std::string>("bssid");
        if (const char* problem = bssid_problem(raw)) throw invalid_field(std::string("'bssid' ") + problem);
        out.values["bssid"] = Bssid(raw).str();
    }
    return out;
}

void check_on_floor(const store::Record& floor, double x, double y) {
    const double width = floor.fields.get<double>("width"), height = floor.fields.get<double>("height");
    if (x < 0 || x > width || y < 0 || y > height)
        throw ApiError(422, "out_of_floor",
                       "(" + shortest(x) + ", " + shortest(y) + ") is not on floor " + std::to_string(floor.id) + " ([0, " +
                           shortest(width) + "] x [0, " + shortest(height) + "])");
}

}  // namespace locus::http
