#include "locus/plan/geojson.hpp"

#include <cmath>
#include <initializer_list>
#include <set>
#include <string>
#include <string_view>

namespace locus::plan {

using nlohmann::json;

namespace {

constexpr std::size_t kMaxFeatures = 100000;
constexpr std::size_t kMaxPoints = 100000;  // per ring or line
constexpr std::size_t kMaxTags = 64;
constexpr std::size_t kMaxLinks = 16;

GeoJsonError invalid_plan(const std::string& where, const std::string& what) {
    return GeoJsonError(where.empty() ? what : where + ": " + what);
}

void only_fields(const json& j, std::initializer_list<std::string_view> allowed, const std::string& where) {
    for (const auto& [key, value] : j.items()) {
        bool ok = false;
        for (auto a : allowed) ok = ok || key == a;
        if (!ok) throw GeoJsonError("unknown field '" + (where.empty() ? key : where + "." + key) + "'");
    }
}

Point point_of(const json& c, const std::string& where) {
    if (!c.is_array() || c.size() < 2 || c.size() > 3 || !c[0].is_number() || !c[1].is_number())
        throw invalid_plan(where, "a position must be [x, y] in metres");
    const double x = c[0].get<double>(), y = c[1].get<double>();
    if (!std::isfinite(x) || !std::isfinite(y)) throw invalid_plan(where, "coordinates must be finite");
    if (std::abs(x) > kMaxPlanCoordinate || std::abs(y) > kMaxPlanCoordinate)
        throw invalid_plan(where, "coordinates must be within ±1e5 m");
    return {x, y};
}

std::vector<Point> line_of(const json& c, std::size_t min_points, const std::string& where) {
    if (!c.is_array() || c.size() < min_points || c.size() > kMaxPoints)
        throw invalid_plan(where, "needs " + std::to_string(min_points) + " to " + std::to_string(kMaxPoints) + " positions");
    std::vector<Point> out;
    out.reserve(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) out.push_back(point_of(c[i], where + "[" + std::to_string(i) + "]"));
    return out;
}

Ring ring_of(const json& c, const std::string& where) {
    auto ring = line_of(c, 4, where);
    if (ring.front().x != ring.back().x || ring.front().y != ring.back().y)
        throw invalid_plan(where, "a ring must be closed (its last position equal to its first)");
    return ring;
}

std::string text_of(const json& props, const char* key, const std::string& where, bool required = false,
                    std::size_t max_length = 200) {
    const auto it = props.find(key);
    if (it == props.end() || it->is_null()) {
        if (required) throw invalid_plan(where, std::string("missing property '") + key + "'");
        return "";
    }
    if (!it->is_string()) throw invalid_plan(where, std::string("'") + key + "' must be a string");
    const auto& s = it->get_ref<const std::string&>();
    if ((required && s.empty()) || s.size() > max_length)
        throw invalid_plan(where, std::string("'") + key + "' must be " + (required ? "1" : "0") + " to " +
                                      std::to_string(max_length) + " characters");
    return s;
}

const json& geometry_of(const json& f, const char* type, const char* other_type, const std::string& where) {
    const auto it = f.find("geometry");
    if (it == f.end() || !it->is_object()) throw invalid_plan(where, "missing geometry");
    const auto t = it->find("type");
    if (t == it->end() || !t->is_string() || (*t != type && (!other_type || *t != other_type)))
        throw invalid_plan(where, std::string("geometry must be a ") + type + (other_type ? std::string(" or ") + other_type : ""));
    if (!it->contains("coordinates")) throw invalid_plan(where, "geometry has no coordinates");
    return *it;
}

Space space_of(const json& f, const json& props, const std::string& where) {
    Space s;
    s.name = text_of(props, "name", where);
    s.kind = text_of(props, "kind", where).empty() ? "room" : text_of(props, "kind", where, false, 64);
    const auto& g = geometry_of(f, "Polygon", nullptr, where);
    const auto& rings = g.at("coordinates");
    if (!rings.is_array() || rings.empty()) throw invalid_plan(where, "a Polygon needs its outer ring");
    s.shape.outer = ring_of(rings[0], where + " outer ring");
    for (std::size_t h = 1; h < rings.size(); ++h) s.shape.holes.push_back(ring_of(rings[h], where + " hole " + std::to_string(h)));
    if (const auto it = props.find("tags"); it != props.end() && !it->is_null()) {
        if (!it->is_array() || it->size() > kMaxTags) throw invalid_plan(where, "'tags' must be an array of at most 64 strings");
        for (const auto& t : *it) {
            if (!t.is_string() || t.get_ref<const std::string&>().empty() || t.get_ref<const std::string&>().size() > 200)
                throw invalid_plan(where, "each tag must be a string of 1 to 200 characters");
            s.tags.push_back(t.get<std::string>());
        }
    }
    if (const auto it = props.find("room_id"); it != props.end() && !it->is_null()) {
        if (!it->is_number_integer() || it->get<std::int64_t>() <= 0) throw invalid_plan(where, "'room_id' must be a room id");
        s.room_id = it->get<std::int64_t>();
    }
    return s;
}

Connector connector_of(const json& f, const json& props, const std::string& where) {
    Connector c;
    c.id = text_of(props, "id", where, true, 64);
    c.name = text_of(props, "name", where);
    const auto kind = connector_kind_named(text_of(props, "kind", where, true, 16));
    if (!kind) throw invalid_plan(where, "'kind' must be stairs, elevator, escalator or ramp");
    c.kind = *kind;
    c.step_free = c.kind == ConnectorKind::elevator || c.kind == ConnectorKind::ramp;
    if (const auto it = props.find("step_free"); it != props.end() && !it->is_null()) {
        if (!it->is_boolean()) throw invalid_plan(where, "'step_free' must be true or false");
        c.step_free = it->get<bool>();
    }
    if (const auto it = props.find("seconds_per_level"); it != props.end() && !it->is_null()) {
        if (!it->is_number() || !std::isfinite(it->get<double>()) || it->get<double>() <= 0 || it->get<double>() > 3600)
            throw invalid_plan(where, "'seconds_per_level' must be a number of seconds in (0, 3600]");
        c.seconds_per_level = it->get<double>();
    }
    c.at = point_of(geometry_of(f, "Point", nullptr, where).at("coordinates"), where);
    if (const auto it = props.find("links"); it != props.end() && !it->is_null()) {
        if (!it->is_array() || it->size() > kMaxLinks) throw invalid_plan(where, "'links' must be an array of at most 16 links");
        for (const auto& l : *it) {
            if (!l.is_object() || !l.contains("floor_id") || !l.at("floor_id").is_number_integer() ||
                l.at("floor_id").get<std::int64_t>() <= 0)
                throw invalid_plan(where, "each link must be {\"floor_id\": id, \"connector\": id}");
            only_fields(l, {"floor_id", "connector"}, where + " link");
            c.links.push_back({l.at("floor_id").get<std::int64_t>(), text_of(l, "connector", where + " link", true, 64)});
        }
    }
    if (const auto it = props.find("poi_id"); it != props.end() && !it->is_null()) {
        if (!it->is_number_integer() || it->get<std::int64_t>() <= 0) throw invalid_plan(where, "'poi_id' must be a POI id");
        c.poi_id = it->get<std::int64_t>();
    }
    return c;
}

Plan parse_features(const json& doc) {
    if (doc.value("type", json()) != "FeatureCollection")
        throw GeoJsonError("a plan must be a GeoJSON FeatureCollection");
    // Members the server writes on GET may come back on a PUT of what was read.
    for (const auto& [key, value] : doc.items()) {
        bool ok = key == "type" || key == "features";
        for (const char* m : kPlanMetaMembers) ok = ok || key == m;
        if (!ok) throw GeoJsonError("unknown field '" + key + "'");
    }
    if (const auto crs = doc.find("crs"); crs != doc.end() && !(crs->is_string() && *crs == "locus:floor-metres"))
        throw GeoJsonError("'crs' must be \"locus:floor-metres\" (a plan in WGS84 is PUT with ?crs=wgs84)");
    const auto it = doc.find("features");
    if (it == doc.end() || !it->is_array() || it->size() > kMaxFeatures)
        throw GeoJsonError("'features' must be an array of at most 100000 features");
    Plan out;
    std::set<std::string, std::less<>> connector_ids;
    for (std::size_t i = 0; i < it->size(); ++i) {
        const json& f = (*it)[i];
        std::string where = "features[" + std::to_string(i) + "]";
        if (!f.is_object() || f.value("type", json()) != "Feature") throw invalid_plan(where, "must be a GeoJSON Feature");
        const auto p = f.find("properties");
        if (p == f.end() || !p->is_object()) throw invalid_plan(where, "needs properties with 'feature'");
        const std::string feature = p->value("feature", json("")).is_string() ? p->value("feature", std::string()) : "";
        if (p->contains("name") && p->at("name").is_string())
            where += " (" + feature + " '" + p->at("name").get<std::string>().substr(0, 60) + "')";
        else if (!feature.empty())
            where += " (" + feature + ")";
        if (feature == "space") {
            only_fields(*p, {"feature", "name", "kind", "tags", "room_id"}, where);
            out.spaces.push_back(space_of(f, *p, where));
        } else if (feature == "wall") {
            only_fields(*p, {"feature"}, where);
            out.walls.push_back({line_of(geometry_of(f, "LineString", nullptr, where).at("coordinates"), 2, where)});
        } else if (feature == "door") {
            only_fields(*p, {"feature", "name"}, where);
            const auto& g = geometry_of(f, "Point", "LineString", where);
            Door d;
            d.name = text_of(*p, "name", where);
            if (g.at("type") == "Point") {
                d.a = d.b = point_of(g.at("coordinates"), where);
            } else {
                const auto line = line_of(g.at("coordinates"), 2, where);
                if (line.size() != 2) throw invalid_plan(where, "a door segment has exactly two positions");
                d.a = line[0];
                d.b = line[1];
            }
            out.doors.push_back(std::move(d));
        } else if (feature == "connector") {
            only_fields(*p, {"feature", "id", "kind", "name", "step_free", "seconds_per_level", "links", "poi_id"}, where);
            auto c = connector_of(f, *p, where);
            if (!connector_ids.insert(c.id).second) throw invalid_plan(where, "connector id '" + c.id + "' is used twice");
            out.connectors.push_back(std::move(c));
        } else {
            throw invalid_plan(where, "properties.feature must be space, wall, door or connector");
        }
    }
    return out;
}

json position(Point p) { return json::array({p.x, p.y}); }

json feature(json geometry, json properties) {
    return {{"type", "Feature"}, {"geometry", std::move(geometry)}, {"properties", std::move(properties)}};
}

}  // namespace

Plan from_geojson(const json& doc) { return parse_features(doc); }

json geojson_positions(const std::vector<Point>& pts) {
    json out = json::array();
    for (const auto& p : pts) out.push_back(position(p));
    return out;
}

json to_geojson(const Plan& p) {
    json features = json::array();
    for (const auto& s : p.spaces) {
        json rings = json::array({geojson_positions(s.shape.outer)});
        for (const auto& h : s.shape.holes) rings.push_back(geojson_positions(h));
        json props = {{"feature", "space"}, {"name", s.name}, {"kind", s.kind}, {"tags", s.tags}};
        props["room_id"] = s.room_id ? json(*s.room_id) : json(nullptr);
        features.push_back(feature({{"type", "Polygon"}, {"coordinates", rings}}, props));
    }
    for (const auto& w : p.walls)
        features.push_back(feature({{"type", "LineString"}, {"coordinates", geojson_positions(w.line)}}, {{"feature", "wall"}}));
    for (const auto& d : p.doors) {
        const bool point = d.a.x == d.b.x && d.a.y == d.b.y;
        json g = point ? json{{"type", "Point"}, {"coordinates", position(d.a)}}
                       : json{{"type", "LineString"}, {"coordinates", geojson_positions({d.a, d.b})}};
        features.push_back(feature(g, {{"feature", "door"}, {"name", d.name}}));
    }
    for (const auto& c : p.connectors) {
        json links = json::array();
        for (const auto& l : c.links) links.push_back({{"floor_id", l.floor_id}, {"connector", l.connector}});
        json props = {{"feature", "connector"}, {"id", c.id}, {"kind", connector_kind_name(c.kind)}, {"name", c.name},
                      {"step_free", c.step_free}, {"links", links}};
        props["seconds_per_level"] = c.seconds_per_level ? json(*c.seconds_per_level) : json(nullptr);
        props["poi_id"] = c.poi_id ? json(*c.poi_id) : json(nullptr);
        features.push_back(feature({{"type", "Point"}, {"coordinates", position(c.at)}}, props));
    }
    return {{"type", "FeatureCollection"}, {"features", features}};
}

}  // namespace locus::plan
