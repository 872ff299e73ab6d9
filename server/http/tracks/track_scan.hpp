#pragma once
// A thin client's WiFi/BLE scan on a track (POST /v1/tracks/{id}/steps, `scans`): localized on
// the track's map exactly as POST /v1/maps/{id}/localize answers a request naming no algorithm
// (the localize service's index, the radio map's stored defaults), and turned into the radio
// fix the track's particle filter takes, as the simulator turns a matcher's answer into one.
#include <cstdint>
#include <string>

#include "localize/service.hpp"
#include "locus/radio_map.hpp"
#include "tracks/fix.hpp"

namespace locus::http {

// The fix's accuracy_m is the RMS spread of the matcher's k best candidates around their mean,
// at least kScanFixFloorM (one candidate is no proof of metre accuracy). Throws ApiError 422
// no_match (naming `where`) when no RP of the map shares an AP with the scan.
inline constexpr double kScanFixFloorM = 1.0;
tracks::Fix scan_fix(const localize::Snapshot& snapshot, double t, const Scan& readings, const std::string& where);

}  // namespace locus::http
