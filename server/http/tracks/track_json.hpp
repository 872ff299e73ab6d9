#pragma once
// The JSON of live tracks (docs/tracks.md): a fix, with lat/lon on a georeferenced floor
// (docs/geo.md), and a track's state. Each costs one cached floor lookup per fix.
#include <nlohmann/json.hpp>

#include "http/plans/floor_geo.hpp"
#include "tracks/fix.hpp"
#include "tracks/service.hpp"

namespace locus::http {

// {t, floor_id, x, y, accuracy_m, heading_deg?, lat?, lon?}
nlohmann::json fix_json(const tracks::Fix& f, FloorGeoCache& geo);
// {id, map_id, label, state, created_at, last_fix_at, fixes, fusion, fusion_options?, latest?, ended_at?}
nlohmann::json track_json(const tracks::TrackInfo& t, FloorGeoCache& geo);

}  // namespace locus::http
