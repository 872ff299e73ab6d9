#include "http/validation.hpp"

#include "http/transmitters/transmitter_fields.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>
#include <vector>

#include "http/api_error.hpp"
#include "locus/geo/georeference.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

std::string type_name(store::FieldType t) {
    switch (t) {
        case store::FieldType::Text: return "a string";
        case store::FieldType::Real: return "a number";
        case store::FieldType::Integer: return "an integer";
    }
    return "a value";
}

std::string at(const std::string& where, std::string_view field) {
    return where.empty() ? std::string(field) : where + "." + std::string(field);
}

// A JSON number that is integral (2 or 2.0) and fits in int64.
std::optional<std::int64_t> as_integer(const json& v) {
    if (v.is_number_integer()) return v.get<std::int64_t>();
    if (v.is_number_float()) {
        const double d = v.get<double>();
        if (std::isfinite(d) && std::floor(d) == d && std::fabs(d) < 9.0e18) return static_cast<std::int64_t>(d);
    }
    return std::nullopt;
}

store::Value check_field(const store::Field& f, const json& v, const std::string& where) {
    const std::string name = at(where, f.name);
    switch (f.type) {
        case store::FieldType::Text: {
            if (!v.is_string()) throw invalid_field("'" + name + "' must be " + type_name(f.type));
            const auto& s = v.get_ref<const std::string&>();
            if (f.required && s.empty()) throw invalid_field("'" + name + "' must not be empty");
            if (s.size() > f.max_length)
                throw invalid_field("'" + name + "' is longer than " + std::to_string(f.max_length) + " characters");
            return s;
        }
        case store::FieldType::Real:
        case store::FieldType::Integer: {
            if (!v.is_number() || v.is_boolean()) throw invalid_field("'" + name + "' must be " + type_name(f.type));
            const double d = v.get<double>();
            if (!std::isfinite(d)) throw invalid_field("'" + name + "' must be finite");
            if (f.type == store::FieldType::Integer && !as_integer(v))
                throw invalid_field("'" + name + "' must be " + type_name(f.type));
            if (f.positive && !(d > 0.0)) throw invalid_field("'" + name + "' must be greater than 0");
            if ((f.min && d < *f.min) || (f.max && d > *f.max))
                throw invalid_field("'" + name + "' is out of range [" + (f.min ? std::to_string(*f.min) : "-inf") +
                                    ", " + (f.max ? std::to_string(*f.max) : "inf") + "]");
            if (f.type == store::FieldType::Integer) return *as_integer(v);
            if (f.angle) return geo::normalise_bearing(d);
            return d;
        }
    }
    return {};
}

std::vector<Rect> check_rects(const json& v, bool create) {
    if (!v.is_array()) throw invalid_field("'rects' must be an array of {xmin, ymin, xmax, ymax}");
    if (create && v.empty()) throw invalid_field("'rects' must hold at least one rectangle");
    if (v.size() > 1000) throw invalid_field("'rects' holds more than 1000 rectangles");
    std::vector<Rect> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const std::string where = "rects[" + std::to_string(i) + "]";
        if (!v[i].is_object()) throw invalid_field("'" + where + "' must be an object");
        only_fields(v[i], {"xmin", "ymin", "xmax", "ymax"}, where);
        auto coordinate = [&](const char* name) {
            const double c = finite_number(v[i], name, where);
            if (std::abs(c) > store::kMaxCoordinate)
                throw invalid_field("'" + at(where, name) + "' is out of range [-1e7, 1e7] (metres)");
            return c;
        };
        const double xmin = coordinate("xmin"), ymin = coordinate("ymin");
        const double xmax = coordinate("xmax"), ymax = coordinate("ymax");
        if (xmin > xmax || ymin > ymax) throw invalid_field("'" + where + "' needs xmin <= xmax and ymin <= ymax");
        out.push_back({xmin, ymin, xmax, ymax});
    }
    return out;
}

// A group of fields given as one object (store::Field::group): null clears every member (a
// create may send it too, meaning none), an object must hold every member and nothing else.
void check_group(const store::Kind& kind, std::string_view group, const json& v, store::Fields& out) {
    const std::string name(group);
    if (v.is_null()) {
        for (const auto& f : kind.fields)
            if (f.group == group) out.values[std::string(f.name)] = std::monostate{};
        return;
    }
    if (!v.is_object()) throw invalid_field("'" + name + "' must be an object or null");
    for (const auto& [key, value] : v.items()) {
        bool known = false;
        for (const auto& f : kind.fields) known = known || (f.group == group && f.key == key);
        if (!known) throw invalid_field("unknown field '" + name + "." + key + "'");
    }
    for (const auto& f : kind.fields) {
        if (f.group != group) continue;
        const auto it = v.find(f.key);
        if (it == v.end() || it->is_null()) throw invalid_field("missing field '" + name + "." + std::string(f.key) + "'");
        store::Field member = f;
        member.name = f.key;
        out.values[std::string(f.name)] = check_field(member, *it, name);
    }
}

}  // namespace

void reject_nul(std::string_view body) {
    if (body.find('\0') != std::string_view::npos)
        throw ApiError(400, "invalid_json", "the request body is not valid JSON (it holds a NUL byte)");
}

void reject_deep(std::string_view body) {
    std::size_t depth = 0;
    bool in_string = false, escaped = false;
    for (const char c : body) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                throw ApiError(400, "invalid_json",
                               "the request body nests arrays and objects deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
}

json parse_object(const std::string& body) {
    reject_nul(body);
    reject_deep(body);
    json j = json::parse(body, nullptr, false);
    if (j.is_discarded()) throw ApiError(400, "invalid_json", "the request body is not valid JSON");
    if (!j.is_object()) throw ApiError(400, "invalid_json", "the request body must be a JSON object");
    return j;
}

store::Fields validated_fields(const store::Kind& kind, const json& body, bool create) {
    store::Fields out;
    std::set<std::string, std::less<>> known{"id"};
    if (!kind.parent_column.empty()) known.emplace(kind.parent_column);
    // Every missing field is named in one answer, so a client (or a person with curl) fixes
    // them all at once: "missing fields 'level', 'width' and 'height'".
    if (create) {
        std::vector<std::string> missing;
        for (const auto& f : kind.fields) {
            const auto it = body.find(f.name);
            if (f.writable && f.required && it == body.end()) missing.emplace_back(f.name);
        }
        if (kind.has_rects && !body.contains("rects")) missing.emplace_back("rects");
        if (missing.size() == 1) throw invalid_field("missing field '" + missing.front() + "'");
        if (!missing.empty()) {
            std::string names;
            for (std::size_t i = 0; i < missing.size(); ++i)
                names += (i == 0 ? "" : i + 1 == missing.size() ? " and " : ", ") + ("'" + missing[i] + "'");
            throw invalid_field("missing fields " + names);
        }
    }
    for (const auto& f : kind.fields) {
        if (!f.group.empty()) {
            if (known.emplace(f.group).second && body.contains(f.group)) check_group(kind, f.group, body.at(f.group), out);
            continue;
        }
        known.emplace(f.name);
        if (!f.writable) continue;  // shown in answers, so clients may echo it back
        const auto it = body.find(f.name);
        if (it == body.end() || (it->is_null() && !f.required && !create)) continue;
        out.values[std::string(f.name)] = check_field(f, *it, "");
    }
    if (kind.has_rects) {
        known.emplace("rects");
        if (body.contains("rects")) out.rects = check_rects(body.at("rects"), create);
    }
    for (const auto& [key, value] : body.items())
        if (!known.count(key)) throw invalid_field("unknown field '" + key + "' for a " + std::string(kind.singular));
    return out;
}

std::int64_t parse_id(std::string_view text, std::string_view what) {
    std::int64_t id = 0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), id);
    if (ec != std::errc() || ptr != text.data() + text.size() || id <= 0)
        throw ApiError(404, "not_found", std::string(what) + " " + std::string(text) + " not found");
    return id;
}

std::int64_t parse_query_integer(const std::string& s, const char* name, std::int64_t lo, std::int64_t hi) {
    std::int64_t v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size() || v < lo || v > hi)
        throw invalid_query(std::string("'") + name + "' must be an integer in [" + std::to_string(lo) + ", " +
                            std::to_string(hi) + "]");
    return v;
}

Page parse_page(const std::optional<std::string>& limit, const std::optional<std::string>& offset) {
    Page p;
    if (limit) p.limit = parse_query_integer(*limit, "limit", 1, kMaxPageLimit);
    if (offset) p.offset = parse_query_integer(*offset, "offset", 0, std::numeric_limits<std::int64_t>::max() / 2);
    return p;
}

double finite_number(const json& obj, std::string_view field, const std::string& where, std::optional<double> min,
                     std::optional<double> max) {
    const auto it = obj.find(field);
    const std::string name = at(where, field);
    if (it == obj.end()) throw invalid_field("missing field '" + name + "'");
    if (!it->is_number()) throw invalid_field("'" + name + "' must be a number");
    const double d = it->get<double>();
    if (!std::isfinite(d)) throw invalid_field("'" + name + "' must be finite");
    if ((min && d < *min) || (max && d > *max)) throw out_of_range(name, d, min, max);
    return d;
}

namespace {
// The shortest text that reads back as the same double: "50", "-120", "0.1", not "50.000000".
std::string plain(double v) {
    char buf[32];
    const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
    return std::string(buf, end);
}
}  // namespace

ApiError out_of_range(const std::string& name, double value, std::optional<double> min, std::optional<double> max) {
    return ApiError(422, "out_of_range",
                    "'" + name + "' = " + plain(value) + " is outside [" + (min ? plain(*min) : "-inf") + ", " +
                        (max ? plain(*max) : "inf") + "]");
}

const char* type_problem(std::string_view type) {
    return type == "wifi" || type == "ble" ? nullptr : "must be \"wifi\" or \"ble\"";
}

const char* bssid_problem(std::string_view raw) {
    if (raw.empty() || raw.size() > 64) return "must be 1 to 64 characters";
    // As a Bssid will see it: surrounding white space goes, control characters inside stay.
    raw = trim_bssid(raw);
    if (raw.empty()) return "must not be blank";
    for (char c : raw)
        if (static_cast<unsigned char>(c) < 0x20) return "holds control characters";
    return nullptr;
}

std::optional<std::string> optional_string(const json& obj, std::string_view field, const std::string& where,
                                           std::size_t max_length) {
    const auto it = obj.find(field);
    if (it == obj.end() || it->is_null()) return std::nullopt;
    const std::string name = at(where, field);
    if (!it->is_string()) throw invalid_field("'" + name + "' must be a string");
    const auto& s = it->get_ref<const std::string&>();
    if (s.empty() || s.size() > max_length)
        throw invalid_field("'" + name + "' must be 1 to " + std::to_string(max_length) + " characters");
    return s;
}

namespace {
std::string parse_type(const json& j, const std::string& where) {
    const auto type = optional_string(j, "type", where, 16).value_or("wifi");
    if (const char* problem = type_problem(type)) throw invalid_field("'" + at(where, "type") + "' " + problem);
    return type;
}

Bssid parse_bssid(const json& j, const std::string& where) {
    const auto it = j.find("bssid");
    if (it == j.end() || it->is_null()) throw invalid_field("missing field '" + at(where, "bssid") + "'");
    if (!it->is_string()) throw invalid_field("'" + at(where, "bssid") + "' must be a string");
    const auto& raw = it->get_ref<const std::string&>();
    if (const char* problem = bssid_problem(raw)) throw invalid_field("'" + at(where, "bssid") + "' " + problem);
    return Bssid(raw);
}

}  // namespace

void only_fields(const json& j, std::initializer_list<std::string_view> allowed, const std::string& where) {
    for (const auto& [key, value] : j.items()) {
        bool ok = false;
        for (auto a : allowed) ok = ok || key == a;
        if (!ok) throw invalid_field("unknown field '" + at(where, key) + "'");
    }
}

Reading parse_reading(const json& j, const std::string& where) {
    if (!j.is_object()) throw invalid_field("'" + where + "' must be an object {type, bssid, rss}");
    only_fields(j, {"type", "bssid", "rss"}, where);
    Reading r;
    r.type = parse_type(j, where);
    r.bssid = parse_bssid(j, where);
    r.rss = finite_number(j, "rss", where, kMinRss, kMaxRss);
    return r;
}

std::vector<Scan> parse_scans(const json& j, const std::string& where) {
    if (!j.is_array() || j.empty()) throw invalid_field("'" + where + "' must be a non-empty array of scans");
    std::vector<Scan> scans;
    scans.reserve(j.size());
    for (std::size_t i = 0; i < j.size(); ++i) {
        const std::string w = where + "[" + std::to_string(i) + "]";
        if (!j[i].is_array()) throw invalid_field("'" + w + "' must be an array of readings");
        Scan scan;
        scan.reserve(j[i].size());
        for (std::size_t k = 0; k < j[i].size(); ++k) scan.push_back(parse_reading(j[i][k], w + "[" + std::to_string(k) + "]"));
        scans.push_back(std::move(scan));
    }
    return scans;
}

Measurement parse_measurement(const json& j, const std::string& where) {
    if (!j.is_object()) throw invalid_field("'" + where + "' must be an object {type, bssid, mean, variance, count}");
    only_fields(j, {"type", "bssid", "mean", "variance", "count"}, where);
    Measurement m;
    m.type = parse_type(j, where);
    m.bssid = parse_bssid(j, where);
    m.stats.mean = finite_number(j, "mean", where, kMinRss, kMaxRss);
    // The variance of values confined to [kMinRss, kMaxRss] with this mean cannot exceed
    // (kMaxRss − mean)(mean − kMinRss) (Bhatia–Davis; at most 60² = 3600). Aggregates past it
    // describe no real samples, and merging them could store what no import would take back.
    // The slack covers rounding in an aggregate computed from real samples.
    const double bound = (kMaxRss - m.stats.mean) * (m.stats.mean - kMinRss);
    m.stats.variance = finite_number(j, "variance", where, 0.0, bound + 1e-6);
    const auto it = j.find("count");
    if (it == j.end()) throw invalid_field("missing field '" + at(where, "count") + "'");
    const auto count = as_integer(*it);
    if (!count || it->is_boolean()) throw invalid_field("'" + at(where, "count") + "' must be an integer");
    if (*count < 1 || *count > kMaxCount)
        throw ApiError(422, "out_of_range", "'" + at(where, "count") + "' must be between 1 and 2^53");
    m.stats.count = *count;
    return m;
}

std::vector<Measurement> parse_measurements(const json& j, const std::string& where) {
    if (!j.is_array()) throw invalid_field("'" + where + "' must be an array of measurements");
    std::vector<Measurement> out;
    out.reserve(j.size());
    for (std::size_t i = 0; i < j.size(); ++i) out.push_back(parse_measurement(j[i], where + "[" + std::to_string(i) + "]"));
    return out;
}

store::RadioMapDocument parse_radiomap_document(const json& doc) {
    if (!doc.is_object()) throw invalid_field("a radio map must be an object {name, description, rps}");
    if (doc.contains("format") && doc.at("format") != "locus-radiomap/1")
        throw invalid_field("'format' must be \"locus-radiomap/1\"");
    store::RadioMapDocument out;
    json meta = json::object();
    for (const char* key : {"name", "description"})
        if (doc.contains(key)) meta[key] = doc.at(key);
    out.fields = validated_fields(store::kind("radiomaps"), meta, true);
    if (!doc.contains("rps") || !doc.at("rps").is_array()) throw invalid_field("'rps' must be an array");
    const auto& rps = doc.at("rps");
    out.rps.reserve(rps.size());
    for (std::size_t i = 0; i < rps.size(); ++i) {
        const std::string where = "rps[" + std::to_string(i) + "]";
        const auto& rp = rps[i];
        if (!rp.is_object()) throw invalid_field("'" + where + "' must be an object");
        only_fields(rp, {"name", "x", "y", "scans", "measurements"}, where);
        json fields = json::object();
        for (const char* key : {"name", "x", "y"})
            if (rp.contains(key)) fields[key] = rp.at(key);
        store::RpDocument typed;
        try {
            const store::Fields f = validated_fields(store::kind("rps"), fields, true);
            typed.name = f.get<std::string>("name");
            typed.at = {f.get<double>("x"), f.get<double>("y")};
        } catch (const ApiError& e) {
            throw ApiError(e.status, e.code, where + ": " + e.what());
        }
        if (rp.contains("scans")) {
            const auto s = as_integer(rp.at("scans"));
            if (!s || *s < 0) throw invalid_field("'" + where + ".scans' must be a non-negative integer");
            if (*s > kMaxCount) throw ApiError(422, "out_of_range", "'" + where + ".scans' must be at most 2^53");
            typed.scans = *s;
        }
        if (rp.contains("measurements")) typed.measurements = parse_measurements(rp.at("measurements"), where + ".measurements");
        out.rps.push_back(std::move(typed));
    }
    if (doc.contains("transmitters")) {
        const auto& txs = doc.at("transmitters");
        if (!txs.is_array()) throw invalid_field("'transmitters' must be an array");
        std::set<std::pair<std::string, std::string>> seen;
        for (std::size_t i = 0; i < txs.size(); ++i) {
            const std::string where = "transmitters[" + std::to_string(i) + "]";
            if (!txs[i].is_object()) throw invalid_field("'" + where + "' must be an object");
            try {
                out.transmitters.push_back(transmitter_fields(txs[i], true));
            } catch (const ApiError& e) {
                throw ApiError(e.status, e.code, where + ": " + e.what());
            }
            const auto& t = out.transmitters.back();
            if (!seen.insert({t.get<std::string>("type"), t.get<std::string>("bssid")}).second)
                throw ApiError(409, "conflict", where + ": a transmitter of that type and bssid is already in the document");
        }
    }
    return out;
}

store::ScanBatch parse_scan_upload(const std::string& text) {
    const json body = parse_object(text);
    only_fields(body, {"upload_id", "scans", "measurements"}, "");
    const bool has_scans = body.contains("scans"), has_measurements = body.contains("measurements");
    if (has_scans == has_measurements)
        throw invalid_field("send exactly one of 'scans' (raw readings) or 'measurements' (aggregates)");
    store::ScanBatch batch;
    batch.upload_id = optional_string(body, "upload_id", "", 200);
    if (has_scans) {
        const auto scans = parse_scans(body.at("scans"), "scans");
        batch.measurements = aggregate_scans(scans);
        batch.scans = static_cast<std::int64_t>(scans.size());
        return batch;
    }
    batch.measurements = parse_measurements(body.at("measurements"), "measurements");
    std::string overflow;
    if (!combine_aggregates(batch.measurements, &overflow))
        throw ApiError(422, "out_of_range", "the counts of '" + overflow + "' in 'measurements' add up past 2^53");
    // Aggregates carry no scan count; the best lower bound is the most-seen AP's count.
    for (const auto& m : batch.measurements) batch.scans = std::max(batch.scans, m.stats.count);
    return batch;
}

}  // namespace locus::http
