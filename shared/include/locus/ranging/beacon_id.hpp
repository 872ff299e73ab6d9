#pragma once
// The text a BLE beacon is named by in scans and in the store (its Bssid), built from its
// parts: an iBeacon as "uuid:major:minor" (the UUID lower-case, 8-4-4-4-12), an Eddystone-UID
// as "namespace:instance" (10 and 6 bytes, lower-case hex). The server and the CLI both build
// them here, so a beacon imported from a file and one created over the API match.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace locus::ranging {

// nullopt unless `uuid` is 32 hex digits (dashes anywhere are dropped) and major, minor are in
// [0, 65535].
std::optional<std::string> ibeacon_id(std::string_view uuid, std::int64_t major, std::int64_t minor);
// nullopt unless `ns` is 20 and `instance` 12 hex digits.
std::optional<std::string> eddystone_id(std::string_view ns, std::string_view instance);

}  // namespace locus::ranging
