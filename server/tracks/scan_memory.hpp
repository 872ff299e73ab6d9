#pragma once
// What a walk_pf track keeps of its scans from one request to the next (docs/tracks.md, "GNSS
// and the phone's offset", "Beacons"): the phone's RSS offset learnt so far (match::DeviceOffset)
// and when each of the map's beacons last counted as a fix (fusion::BeaconGate). Held with the
// track's filter (tracks/fusion.hpp) and copied with it, so a refused request teaches nothing;
// it starts afresh where the filter does (a resume at a stored fix).
#include "locus/match/device_offset.hpp"
#include "locus/motion/fusion/beacon.hpp"

namespace locus::tracks {

struct ScanMemory {
    match::DeviceOffset offset;
    fusion::BeaconGate beacons;
};

}  // namespace locus::tracks
