#pragma once
// ekf_ranging tracks (tracks/fusion.hpp): the map's known transmitters as fusion::RangingEkf's
// anchors, and a scan's readings of them, both keyed as ranging localize keys a transmitter
// (transmitter_key), so the filter hears what POST …/localize by multilateration hears.
// Eigen first: cpp-httplib pulls in <resolv.h>, whose `_res` macro breaks Eigen.
#include "tracks/fusion.hpp"

#include <memory>
#include <vector>

#include "http/localize/ranging_localize.hpp"
#include "locus/match/query.hpp"

namespace locus::http {

std::shared_ptr<const tracks::FloorAnchors> floor_anchors(const KnownTransmitters& known);
// The query's readings of known transmitters (of any floor), stamped t: the kMaxEkfReadings
// strongest. The filter's update solves a system as large as the readings, cubic in their
// count, under the lock all thin-client fusion shares; multilateration keeps at most 30 too.
inline constexpr std::size_t kMaxEkfReadings = 30;
std::vector<fusion::AnchorReading> anchor_readings(const KnownTransmitters& known, const match::Query& query, double t);

}  // namespace locus::http
