#pragma once
// The JSON of live tracks (docs/tracks.md): a fix, with lat/lon on a georeferenced floor
// (docs/geo.md) and its room and the POIs near it (http/places_json.hpp), and a track's state.
// Each costs two cached floor lookups per fix.
#include <nlohmann/json.hpp>

#include "http/places_json.hpp"
#include "tracks/fix.hpp"
#include "tracks/service.hpp"
#include "tracks/scan_area.hpp"

namespace locus::http {

// {t, floor_id, x, y, accuracy_m, heading_deg?, lat?, lon?, room, nearby}
nlohmann::json fix_json(const tracks::Fix& f, PositionViews& views);
// A scan's fix with where it was matched: the fix's JSON and `subarea`, null (the whole map
// from the start) or {x, y, radius_m, fell_back} (tracks::ScanArea).
nlohmann::json scan_fix_json(const tracks::Fix& f, const tracks::ScanArea& area, PositionViews& views);
// {id, map_id, label, state, created_at, last_fix_at, fixes, fusion, fusion_options?, latest?, ended_at?}
nlohmann::json track_json(const tracks::TrackInfo& t, PositionViews& views);

}  // namespace locus::http
