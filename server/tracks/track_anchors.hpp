#pragma once
// ekf_ranging tracks (tracks/fusion.hpp): the map's known transmitters as fusion::RangingEkf's
// anchors, and a scan's readings of them, both keyed as the ranging localize keys a
// transmitter (transmitters::transmitter_key), so the filter hears what POST …/localize by
// multilateration hears.
#include <cstddef>
#include <memory>
#include <vector>

#include "locus/match/query.hpp"
#include "tracks/fusion.hpp"
#include "transmitters/ranging_scan.hpp"

namespace locus::tracks {

std::shared_ptr<const FloorAnchors> floor_anchors(const transmitters::KnownTransmitters& known);
// The query's readings of known transmitters (of any floor), stamped t: the kMaxEkfReadings
// strongest. The filter's update solves a system as large as the readings, cubic in their
// count, under the lock all thin-client fusion shares; multilateration keeps at most 30 too.
inline constexpr std::size_t kMaxEkfReadings = 30;
std::vector<fusion::AnchorReading> anchor_readings(const transmitters::KnownTransmitters& known, const match::Query& query, double t);

}  // namespace locus::tracks
