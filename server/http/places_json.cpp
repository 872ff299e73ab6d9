#include "http/places_json.hpp"

namespace locus::http {

using nlohmann::json;

json nearby_json(const FloorPlaces* places, Point at) {
    json out = json::array();
    if (!places) return out;
    for (const auto& n : places->nearby(at))
        out.push_back({{"poi_id", n.poi->id}, {"name", n.poi->name}, {"kind", n.poi->kind}, {"distance_m", n.distance_m}});
    return out;
}

void add_places(json& j, const FloorPlaces* places, Point at) {
    const Room* room = places ? places->room_at(at) : nullptr;
    j["room"] = room ? json{{"id", room->id}, {"name", room->name}} : json(nullptr);
    j["nearby"] = nearby_json(places, at);
}

}  // namespace locus::http
