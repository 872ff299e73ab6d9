#pragma once
// A PUTMC walk posted to a live track as a phone posts it, and the server's own filter's
// estimate at each scan: what `locus eval walks` reports as walk_pf (docs/fusion.md, "Real
// walks: PUTMC"), so that its figure is what a phone gets. The batches are
// tools/putmc_thin.hpp's: one POST /v1/tracks/{id}/steps per WiFi scan, with the steps the
// detector confirmed since the previous scan, headings as the compass reads them (from north;
// a floor without a georeference learns the rotation), the track opened with only its map (the
// server's defaults). The walk's clock is moved so that the walk ends now (the server refuses
// fixes from the future and older than it keeps). A scan no RP hears (422 no_match) is posted
// again without it and steps before the track's first fix (422 cannot_fuse) are dropped, as a
// phone would go on. Each scan's own fix is kept too (where the track's subarea matched it).
//
// Cost: one request per scan; the track is closed at the end.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "datasets/putmc.hpp"
#include "locus/api/client.hpp"
#include "live_post.hpp"
#include "locus/geometry.hpp"

namespace locus::tools::walks {

struct LiveWalk {
    std::vector<std::optional<Point>> at_scan;  // the track's latest fused fix after each scan's request (floor frame)
    std::vector<std::optional<Point>> scan_fix;  // the scan's own fix (the request's scan_fixes), none when refused
    std::int64_t track_id = 0;
    std::string token;  // the owner's, to read the track afterwards
    PostCounts posted;
};

// subarea false: the track opened with fusion_options.subarea false (its scans matched on the
// whole map), to measure what the subarea does.
LiveWalk live_walk(api::Client& client, std::int64_t map_id, const datasets::putmc::Walk& walk, bool subarea = true);

}  // namespace locus::tools::walks
