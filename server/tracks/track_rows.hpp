#pragma once
// The store's rows of a track (store/track_repository.hpp) as the service's types, and back:
// a field-by-field copy, no I/O.
#include <string>

#include "store/track_repository.hpp"
#include "tracks/track_info.hpp"

namespace locus::tracks {

inline State state_of(const std::string& s) { return s == "live" ? State::live : s == "closed" ? State::closed : State::gone; }

// Without its latest fix and count, which are rows of their own.
inline TrackInfo info_of(const store::TrackRow& r) {
    TrackInfo info;
    info.id = r.id;
    info.map_id = r.map_id.value_or(0);
    info.label = r.label;
    info.state = state_of(r.state);
    info.created_at = r.created_at;
    info.last_fix_at = r.last_fix_at;
    info.ended_at = r.ended_at;
    info.fusion = fusion_method_of(r.fusion).value_or(FusionMethod::walk_pf);
    if (r.fusion_options) info.fusion_options = fusion_options_of_text(*r.fusion_options);
    return info;
}

inline Fix fix_of(const store::FixRow& r) { return Fix{r.t, r.floor_id, r.x, r.y, r.accuracy_m, r.heading_deg}; }
inline store::FixRow row_of(const Fix& f) { return store::FixRow{f.t, f.floor_id, f.x, f.y, f.accuracy_m, f.heading_deg}; }

}  // namespace locus::tracks
