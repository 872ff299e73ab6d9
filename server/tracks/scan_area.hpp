#pragma once
// The dynamic subarea of a track's scans (docs/spec.md §4.2, Lu et al. 2016; docs/tracks.md,
// "Subarea"), and where a scan was matched (answered with each of /steps' scan_fixes and by a
// localize naming the track).
#include <algorithm>
#include <optional>

#include "locus/match/options.hpp"
#include "tracks/fix.hpp"

namespace locus::tracks {

// Only the RPs round where the track is count, as far as its own uncertainty (kSubareaSigmas ×
// its accuracy) and the walker's reach since (kSubareaWalkMps × the time) allow, plus
// kSubareaBaseM. Chosen on the IPIN 2023 folds and PUTMC (docs/results.md, "The subarea"):
// wider changed nothing, narrower cost PUTMC.
inline constexpr double kSubareaBaseM = 3.0, kSubareaSigmas = 2.0, kSubareaWalkMps = 1.5;

// The subarea at time t round a track's estimate.
inline match::Near subarea_round(const Fix& estimate, double t) {
    return {{estimate.x, estimate.y}, kSubareaBaseM + kSubareaSigmas * estimate.accuracy_m + kSubareaWalkMps * std::max(0.0, t - estimate.t)};
}

// `near`: the subarea round the track's filter's estimate (walk_pf, docs/tracks.md "Subarea");
// fell_back when none of its RPs shares an AP with the scan and the whole map answered. No
// `near`: the whole map from the start (the track's first scan, its subarea turned off, or a
// method that takes none).
struct ScanArea {
    std::optional<match::Near> near;
    bool fell_back = false;
};

}  // namespace locus::tracks
