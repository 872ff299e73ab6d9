#pragma once
// What a thin client's filter run asks its caller for while it holds the track's filter
// (tracks/fusion_sessions.hpp): the floors' georeferences, for GNSS, and walk_pf's scans, which
// are localized there because each is shifted by the phone's RSS offset the filter's session
// has learnt so far and then teaches it, and its beacons count once per interval
// (docs/tracks.md, "GNSS and the phone's offset", "Beacons"). The
// HTTP layer's localizer and georeference cache implement it (tracks/thin_client.hpp). Plain
// declarations, no Eigen: service.hpp includes this.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "tracks/fix.hpp"

namespace locus::geo {
class FloorToEarth;
}
namespace locus::tracks {

struct ScanMemory;  // tracks/scan_memory.hpp

class RunSources {
public:
    virtual ~RunSources() = default;
    // The floor's georeference; null when it has none (its GNSS fixes are not used).
    virtual std::shared_ptr<const geo::FloorToEarth> georeference(std::int64_t floor_id) = 0;
    // The batch's scans as radio fixes, in time order: each localized with the memory's offset
    // added and then teaching it, and its strong readings of the map's beacons as fixes at them
    // (one per beacon per interval, the memory's gate), unless at or before `done_t` (a retried
    // scan taught it the first time).
    // `estimate`: where the filter is before the batch (nullopt before it started), round
    // which the scans are matched first (the dynamic subarea, docs/tracks.md).
    virtual std::vector<Fix> scans(ScanMemory& memory, std::optional<double> done_t, const std::optional<Fix>& estimate) = 0;
};

}  // namespace locus::tracks
