#pragma once
// The body of POST .../localize as a phone sends it, for the tools that replay scans
// (`locus bench localize`, bench/localize_request_bench.cpp).
#include <string>
#include <vector>

#include "locus/radio_map.hpp"

namespace locus::tools {

// {"algorithm": .., "scans": [[{"bssid", "rss"[, "type"]}, ..], ..]}: whole dBm as JSON
// integers, the way phones report RSS (and UJIIndoorLoc stores it); "type" only when not wifi.
std::string localize_body(const std::vector<Scan>& scans, const std::string& algorithm);

}  // namespace locus::tools
