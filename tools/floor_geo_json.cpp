#include "floor_geo_json.hpp"

namespace locus::tools {

std::optional<geo::Georeference> georeference_of(const nlohmann::json& floor) {
    if (!floor.contains("geo") || !floor.at("geo").is_object()) return std::nullopt;
    const nlohmann::json& g = floor.at("geo");
    geo::Georeference ref;
    ref.at = {g.at("lat").get<double>(), g.at("lon").get<double>()};
    ref.anchor = {g.at("x").get<double>(), g.at("y").get<double>()};
    ref.bearing_deg = g.at("bearing_deg").get<double>();
    return ref;
}

}  // namespace locus::tools
