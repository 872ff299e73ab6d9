// POST /v1/maps/{id}/route: from one place to another through the map's floor plans.
//
//   {"from": {"floor_id", "x", "y"} | {"room_id"} | {"poi_id"}, "to": …,
//    "options": {"step_free": false, "avoid": [room ids], "walking_speed": 1.3}}
//
// answers the length, the time, a polyline per floor, the connectors taken, turn-by-turn
// steps and the route as GeoJSON; 422 no_route says which constraint blocked it.
#include <cmath>
#include <string>

#include "http/app.hpp"
#include "http/plans/plan_json.hpp"
#include "http/routing/route_json.hpp"
#include "http/validation.hpp"

namespace locus::http {

using nlohmann::json;

namespace {

const char* step_kind(plan::StepKind k) {
    switch (k) {
        case plan::StepKind::walk: return "walk";
        case plan::StepKind::slight_left: return "slight_left";
        case plan::StepKind::turn_left: return "turn_left";
        case plan::StepKind::sharp_left: return "sharp_left";
        case plan::StepKind::slight_right: return "slight_right";
        case plan::StepKind::turn_right: return "turn_right";
        case plan::StepKind::sharp_right: return "sharp_right";
        case plan::StepKind::take_connector: return "take_connector";
        case plan::StepKind::arrive: return "arrive";
    }
    return "walk";
}

std::int64_t positive_id(const json& j, const char* field, const std::string& where) {
    const auto it = j.find(field);
    if (!it->is_number_integer() || it->get<std::int64_t>() <= 0)
        throw invalid_field("'" + where + "." + field + "' must be a positive integer id");
    return it->get<std::int64_t>();
}

}  // namespace

json route_json(const plan::Route& r, FloorGeoCache& geo) {
    json legs = json::array(), transfers = json::array(), steps = json::array(), features = json::array();
    for (const auto& leg : r.legs) {
        legs.push_back({{"floor_id", leg.floor_id}, {"level", leg.level}, {"length_m", leg.length_m}, {"path", positions_json(leg.path)}});
        if (const auto earth = geo.of_floor(leg.floor_id)) {
            json& lat_lon = legs.back()["path_lat_lon"] = json::array();
            for (const Point p : leg.path) {
                const auto g = earth->to_geodetic(p);
                lat_lon.push_back({g.lat, g.lon});
            }
        }
        features.push_back({{"type", "Feature"},
                            {"geometry", {{"type", "LineString"}, {"coordinates", positions_json(leg.path)}}},
                            {"properties", {{"floor_id", leg.floor_id}, {"level", leg.level}, {"length_m", leg.length_m}}}});
    }
    for (const auto& t : r.transfers)
        transfers.push_back({{"kind", plan::connector_kind_name(t.kind)}, {"name", t.name}, {"from_level", t.from_level},
                             {"to_level", t.to_level}, {"seconds", t.seconds}});
    for (const auto& s : r.steps) {
        json step = {{"kind", step_kind(s.kind)}, {"text", s.text}};
        if (s.kind == plan::StepKind::walk) step["distance_m"] = s.distance_m;
        if (s.kind == plan::StepKind::take_connector) {
            step["connector"] = plan::connector_kind_name(s.connector);
            step["from_level"] = s.from_level;
            step["to_level"] = s.to_level;
        }
        steps.push_back(std::move(step));
    }
    json from = {{"floor_id", r.legs.front().floor_id}, {"x", r.start.x}, {"y", r.start.y}};
    json to = {{"floor_id", r.legs.back().floor_id}, {"x", r.end.x}, {"y", r.end.y}};
    add_lat_lon(from, geo.of_floor(r.legs.front().floor_id).get(), r.start);
    add_lat_lon(to, geo.of_floor(r.legs.back().floor_id).get(), r.end);
    return {{"length_m", r.length_m},
            {"time_s", r.time_s},
            {"from", std::move(from)},
            {"to", std::move(to)},
            {"legs", legs},
            {"transfers", transfers},
            {"steps", steps},
            {"geojson", {{"type", "FeatureCollection"}, {"features", features}}}};
}

// A place given as a position, a room (its centre) or a POI, on a floor of this map. An
// unknown room, POI or floor is a bad field of this request (422), not a missing resource:
// the resource the path names is the map, and it exists.
plan::Endpoint App::endpoint_of(const json& body, const char* name, std::int64_t map_id) {
    try {
        return place_of(body, name, map_id);
    } catch (const store::NotFound& e) {
        throw invalid_field(std::string("'") + name + "': " + e.what());
    }
}

plan::Endpoint App::place_of(const json& body, const char* name, std::int64_t map_id) {
    const auto it = body.find(name);
    if (it == body.end() || !it->is_object())
        throw invalid_field(std::string("'") + name + "' must be {floor_id, x, y}, {room_id} or {poi_id}");
    const json& j = *it;
    plan::Endpoint e;
    std::int64_t floor_id = 0;
    if (j.contains("room_id")) {
        only_fields(j, {"room_id"}, name);
        const auto room = store_.get(store::kind("rooms"), positive_id(j, "room_id", name));
        floor_id = *room.parent_id;
        Room r;
        r.rects = room.fields.rects.value_or(std::vector<Rect>{});
        if (r.rects.empty()) throw invalid_field(std::string("'") + name + "': room " + std::to_string(room.id) + " has no rectangles to start from");
        e.at = r.centre();
    } else if (j.contains("poi_id")) {
        only_fields(j, {"poi_id"}, name);
        const auto poi = store_.get(store::kind("pois"), positive_id(j, "poi_id", name));
        floor_id = *poi.parent_id;
        e.at = {poi.fields.get<double>("x"), poi.fields.get<double>("y")};
    } else {
        only_fields(j, {"floor_id", "x", "y"}, name);
        if (!j.contains("floor_id")) throw invalid_field(std::string("'") + name + "' needs floor_id, room_id or poi_id");
        floor_id = positive_id(j, "floor_id", name);
        e.at = {finite_number(j, "x", name, -plan::kMaxPlanCoordinate, plan::kMaxPlanCoordinate),
                finite_number(j, "y", name, -plan::kMaxPlanCoordinate, plan::kMaxPlanCoordinate)};
    }
    const auto floor = store_.get(store::kind("floors"), floor_id);  // NotFound for an unknown floor
    if (store_.get(store::kind("buildings"), *floor.parent_id).parent_id != map_id)
        throw invalid_field(std::string("'") + name + "' is on floor " + std::to_string(floor_id) + ", which is not in map " +
                            std::to_string(map_id));
    e.floor_id = floor_id;
    return e;
}

void App::install_route_routes() {
    server_.Post(R"(/v1/maps/(\d+)/route)", [this](const httplib::Request& req, httplib::Response& res) {
        respond(req, res, [&] {
            const auto map_id = parse_id(req.matches[1].str(), "map");
            const json body = parse_object(req.body);
            only_fields(body, {"from", "to", "options"}, "");
            const auto building = router_.building(map_id);  // NotFound for an unknown map
            const plan::Endpoint from = endpoint_of(body, "from", map_id), to = endpoint_of(body, "to", map_id);
            plan::RouteOptions options;
            if (const auto o = body.find("options"); o != body.end()) {
                if (!o->is_object()) throw invalid_field("'options' must be an object");
                only_fields(*o, {"step_free", "avoid", "walking_speed"}, "options");
                if (const auto sf = o->find("step_free"); sf != o->end()) {
                    if (!sf->is_boolean()) throw invalid_field("'options.step_free' must be true or false");
                    options.step_free = sf->get<bool>();
                }
                if (o->contains("walking_speed")) options.walking_speed = finite_number(*o, "walking_speed", "options", 0.1, 10.0);
                if (const auto av = o->find("avoid"); av != o->end()) {
                    if (!av->is_array() || av->size() > 1000) throw invalid_field("'options.avoid' must be an array of room ids");
                    for (const auto& id : *av) {
                        if (!id.is_number_integer() || id.get<std::int64_t>() <= 0)
                            throw invalid_field("'options.avoid' must be an array of room ids");
                        for (const auto& s : plan::spaces_of_room(*building, id.get<std::int64_t>())) options.avoid.push_back(s);
                    }
                }
            }
            // The graph is the caller's to read; the search's arrays are this worker's own.
            thread_local plan::RouteScratch scratch;
            const plan::Route r = plan::route(*building, from, to, options, scratch);
            if (r.status != plan::RouteStatus::ok)
                throw ApiError(422, "no_route", plan::to_string(r.status));
            return std::pair{200, route_json(r, geo_)};
        });
    });
}

}  // namespace locus::http
