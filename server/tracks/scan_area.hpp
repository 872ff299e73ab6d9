#pragma once
// Where a track's scan was matched (answered with each of /steps' scan_fixes).
#include <optional>

#include "locus/match/options.hpp"

namespace locus::tracks {

// `near`: the subarea round the track's filter's estimate (walk_pf, docs/tracks.md "Subarea");
// fell_back when none of its RPs shares an AP with the scan and the whole map answered. No
// `near`: the whole map from the start (the track's first scan, its subarea turned off, or a
// method that takes none).
struct ScanArea {
    std::optional<match::Near> near;
    bool fell_back = false;
};

}  // namespace locus::tracks
