#pragma once
// The transmitters file of `locus import transmitters`: CSV with a header row naming the
// columns, in any order. Columns: name, type (wifi | ble; default wifi), bssid, x, y, z,
// tx_power, path_loss_exponent, wall_attenuation, and for beacons given by their parts uuid,
// major, minor (iBeacon) or namespace, instance (Eddystone). An empty cell leaves the field
// out. Each row becomes the JSON body of POST /v1/floors/{id}/transmitters.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace locus::tools {

struct TransmitterRows {
    std::vector<nlohmann::json> bodies;    // one per data row, in file order
    std::vector<int> lines;                // each body's line in the file
    std::vector<std::string> errors;       // "line 4: 'x' is not a number"; none: all rows good
};

// Reads the whole file; a malformed row is an error, never skipped silently. Checks what the
// file alone can tell (numbers, required columns, one id form per row); the server checks
// the rest.
TransmitterRows parse_transmitter_csv(std::string_view text);

}  // namespace locus::tools
