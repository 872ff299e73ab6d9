#pragma once
// A PUTMC walk as a thin-client phone sends it to a live track (docs/tracks.md, "Thin
// clients"): one POST /v1/tracks/{id}/steps per WiFi scan, holding the steps the detector
// confirmed since the previous scan (in the phone's compass frame: the server's walk_pf learns
// the rotation) and the scan's readings. Used by the replays and load tests that post real
// walks to a server, and by thin_fusion_bench without HTTP. Pure: no I/O.
#include <vector>

#include "datasets/putmc.hpp"
#include "phone_steps.hpp"

namespace locus::tools::walks {

struct ThinBatch {
    double t_s = 0.0;               // the scan's time (the phone's boot clock)
    std::vector<PhoneStep> steps;   // confirmed after the previous scan, at or before t_s
    const datasets::putmc::WifiScan* scan = nullptr;  // into the walk passed in: keep it alive
    Point truth;                    // the scan's ground-truth point, PUTMC frame (y down)
};

// One batch per scan of `walk`, in time order; steps confirmed after the last scan are left out.
std::vector<ThinBatch> thin_batches(const datasets::putmc::Walk& walk);

}  // namespace locus::tools::walks
