#pragma once
// A thin client's batch on its track (POST /v1/tracks/{id}/steps), as read and checked by the
// HTTP layer and fused by tracks/thin_client.hpp. Plain data, no Eigen (so the HTTP layer's
// request reader may include it after cpp-httplib).
#include <string>
#include <vector>

#include "locus/radio_map.hpp"
#include "tracks/fix.hpp"

namespace locus::tracks {

// A scan of the batch: `where` names it in errors ("scans[2]").
struct TimedScan {
    double t = 0;
    Scan readings;
    std::string where;
};

// The batch, checked: each list in time order.
struct StepsInput {
    std::vector<Step> steps;
    std::vector<Fix> fixes;
    std::vector<TimedScan> scans;
    std::vector<Pressure> pressure;
    std::vector<Gnss> gnss;
};

}  // namespace locus::tracks
