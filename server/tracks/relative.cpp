#include "tracks/relative.hpp"

#include <cmath>
#include <numbers>

#include "store/kinds.hpp"

namespace locus::tracks {

double bearing_deg(const Fix& from, const Fix& to) {
    double bearing = std::atan2(to.x - from.x, to.y - from.y) * 180.0 / std::numbers::pi;
    if (bearing < 0) bearing += 360.0;
    return bearing;
}

double turned_deg(double bearing_deg, double heading_deg) {
    double rel = bearing_deg - heading_deg;
    while (rel > 180) rel -= 360;
    while (rel <= -180) rel += 360;
    return rel;
}

std::string direction_text(double relative_deg) {
    const double a = std::fabs(relative_deg);
    if (a <= 10) return "ahead";
    if (a >= 170) return "behind";
    const std::string side = relative_deg > 0 ? "right" : "left";
    const std::string deg = std::to_string(static_cast<int>(std::lround(a))) + "\u00b0 " + side;
    return (a < 90 ? "ahead, " : "behind, ") + deg;
}

Relative relative(Service& svc, store::Store& store, const BuildingOf& building_of, std::int64_t a_id, std::int64_t b_id) {
    const auto a = svc.info(a_id), b = svc.info(b_id);
    if (a.map_id != b.map_id)
        throw Unrelated(Unrelated::Why::other_map, "tracks " + std::to_string(a_id) + " and " + std::to_string(b_id) + " are on different maps");
    if (!a.latest || !b.latest) throw Unrelated(Unrelated::Why::no_fix, "track " + std::to_string(a.latest ? b_id : a_id) + " has no fix yet");
    const auto level = [&store](std::int64_t floor_id) { return store.get(store::kind("floors"), floor_id).fields.get<std::int64_t>("level"); };
    Relative out;
    out.from = *a.latest;
    out.to = *b.latest;
    const double now = Service::now();
    out.from_age_s = now - out.from.t;
    out.to_age_s = now - out.to.t;
    out.straight_distance_m = std::hypot(out.to.x - out.from.x, out.to.y - out.from.y);
    out.bearing_deg = bearing_deg(out.from, out.to);
    out.floor_difference = level(out.to.floor_id) - level(out.from.floor_id);
    if (out.from.heading_deg) {
        out.relative_bearing_deg = turned_deg(out.bearing_deg, *out.from.heading_deg);
        out.direction = direction_text(*out.relative_bearing_deg);
    }
    try {
        const auto building = building_of(a.map_id);
        thread_local plan::RouteScratch scratch;  // the HTTP worker's, as the route endpoint's
        plan::Route r = plan::route(*building, {out.from.floor_id, {out.from.x, out.from.y}}, {out.to.floor_id, {out.to.x, out.to.y}}, {}, scratch);
        if (r.status == plan::RouteStatus::ok) out.route = std::move(r);
        else out.walking_problem = plan::to_string(r.status);
    } catch (const store::NotFound& e) {
        out.walking_problem = e.what();
    } catch (const NoGraph& e) {
        out.walking_problem = e.what();
    }
    return out;
}

}  // namespace locus::tracks
