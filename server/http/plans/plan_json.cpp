#include "http/plans/plan_json.hpp"

#include "http/api_error.hpp"
#include "locus/plan/geojson.hpp"

namespace locus::http {

using nlohmann::json;

plan::Plan parse_plan(const json& doc) {
    try {
        return plan::from_geojson(doc);
    } catch (const plan::GeoJsonError& e) {
        throw ApiError(422, "invalid_plan", e.what());
    }
}

json positions_json(const std::vector<Point>& pts) { return plan::geojson_positions(pts); }

json plan_json(const store::StoredPlan& stored) {
    json doc = plan::to_geojson(stored.plan);
    return {{"type", "FeatureCollection"}, {"floor_id", stored.floor_id}, {"version", stored.version},
            {"updated_at", stored.updated_at}, {"features", std::move(doc["features"])}};
}

}  // namespace locus::http
