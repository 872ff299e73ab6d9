#pragma once
// The true path of a recorded walk, as points for a live track (`locus track`): a walk file of
// ours (its truth, once a second) or a PUTMC walk directory (the ground-truth point of each
// scan, its y flipped onto the floor with the floor's height, as `locus import putmc` does).
#include <string>
#include <vector>

#include "live_track.hpp"

namespace locus::tools {

// Throws CommandError when the walk has no ground truth to replay.
std::vector<LivePoint> walk_points(const std::string& path, double floor_height_m, double every_s = 1.0);

}  // namespace locus::tools
