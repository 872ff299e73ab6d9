#pragma once
// A thin client's scan as the radio fix a track's filter takes (tracks/fusion.hpp): from the
// radio map's match, as the simulator turns a matcher's answer into one, or from a ranging fix
// on the map's transmitters, carried for its covariance. Pure: a few small matrices per fix.
#include <cstdint>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/match/localize.hpp"
#include "locus/ranging/trilateration.hpp"
#include "tracks/fusion.hpp"

namespace locus::tracks {

// The fix's accuracy_m is the RMS spread of the matcher's k best candidates (`spread`) around
// their mean, at least kScanFixFloorM: one candidate is no proof of metre accuracy.
inline constexpr double kScanFixFloorM = 1.0;
Fix matched_fix(double t, std::int64_t floor_id, Point at, const std::vector<Point>& spread);
// The spread matched_fix takes from a matcher's answer: its best max(1, k) candidates'
// positions (k: the matcher's Options::k), or the answer's own point when it lists none.
std::vector<Point> candidate_spread(const match::Result& result, int k);

// A ranging fix's accuracy_m is the σ per axis of its covariance (fusion::ranging_covariance),
// as a matched fix's is of its spread; the ranging fix itself goes along for kalman_ranging's R.
RadioFix ranged_fix(double t, std::int64_t floor_id, const ranging::Fix& fix);

}  // namespace locus::tracks
