#include "http/tracks/track_json.hpp"

namespace locus::http {

using nlohmann::json;

json fix_json(const tracks::Fix& f, PositionViews& views) {
    json j = {{"t", f.t}, {"floor_id", f.floor_id}, {"x", f.x}, {"y", f.y}, {"accuracy_m", f.accuracy_m}};
    if (f.heading_deg) j["heading_deg"] = *f.heading_deg;
    add_lat_lon(j, views.geo.of_floor(f.floor_id).get(), {f.x, f.y});  // when the floor is georeferenced
    add_places(j, views.places.of_floor(f.floor_id).get(), {f.x, f.y});
    return j;
}

json scan_fix_json(const tracks::Fix& f, const tracks::ScanArea& area, PositionViews& views) {
    json j = fix_json(f, views);
    j["subarea"] = area.near ? json{{"x", area.near->at.x}, {"y", area.near->at.y}, {"radius_m", area.near->radius}, {"fell_back", area.fell_back}}
                             : json(nullptr);
    return j;
}

json track_json(const tracks::TrackInfo& t, PositionViews& views) {
    json j = {{"id", t.id},
              {"map_id", t.map_id},
              {"label", t.label},
              {"state", tracks::state_name(t.state)},
              {"created_at", t.created_at},
              {"last_fix_at", t.last_fix_at},
              {"fixes", t.fixes},
              {"fusion", tracks::fusion_method_name(t.fusion)}};
    if (!t.fusion_options.empty()) j["fusion_options"] = tracks::fusion_options_json(t.fusion_options);
    if (t.latest) j["latest"] = fix_json(*t.latest, views);  // absent before the first fix
    if (t.ended_at) j["ended_at"] = *t.ended_at;
    return j;
}

}  // namespace locus::http
