#pragma once
// The IPIN 2023 Track 3 venue as `locus import ipin` and `locus eval ipin` lay it out
// (docs/ipin-import.md): one building "100", floors 0, -1, -2
// sharing one frame, georeferenced from the data set's local frame, and the competition's
// beacons file.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "locus/geo/georeference.hpp"

namespace locus::tools::ipin {

// The data set's local frame: east/north metres about this point (its README).
inline constexpr double kOriginLat = 49.46115;
inline constexpr double kOriginLon = 11.11115;
// A floor's frame must hold its transmitters and RPs in [0, width] x [0, height], so the local
// frame's origin sits at this floor point; the landmarks span about 100 m x 50 m around it
// (east -49..51 m, north -28..20 m), the surveyed reference points reach 63 m west.
inline constexpr double kOriginX = 70.0;
inline constexpr double kOriginY = 40.0;
inline constexpr double kWidth = 140.0;
inline constexpr double kHeight = 80.0;

// The georeference every floor of the venue gets: the local frame's axes, x east and y north
// (bearing 0), origin at (kOriginX, kOriginY).
geo::Georeference venue_georeference();

struct FloorSpec {
    int level;             // the POSI floor id, also the floor's level
    const char* name;
    double elevation_m;    // above floor 0 (docs/ipin-import.md: from the README's pressure steps)
};
// Floors 0, -1, -2 in that order.
const std::vector<FloorSpec>& venue_floors();

// "be:ac:20:23:00:0n" (two hex digits for n up to 255).
std::string beacon_mac(int number);

// The number n of the logs' beacon (MAC be:ac:20:23:00:0n, minor n) that stands where
// BLE_Locations.csv puts BLE<csv_number>. The data set's README presumes they are equal; the
// walks' strongest readings say so for 1, 4, 5 and 6, but put beacon 2 at BLE3's place and
// beacon 3 at BLE2's (4.2 and 1.5 m off, on that row's floor; 20-25 m and a floor off their
// own rows) (docs/ipin-import.md, "The beacons": `locus eval ipin --json`'s `beacons`).
int logged_beacon(int csv_number);

// The trial files of DIR/trials whose names match any of the globs (fnmatch), sorted by name.
// Throws std::runtime_error when DIR/trials is not a folder.
std::vector<std::string> trial_files(const std::string& dir, const std::vector<std::string>& globs);

// "IPIN2023_T3_TrainingTrial01_repetition02.txt" -> "T01_R02" (else the file's stem).
std::string trial_label(const std::string& path);

}  // namespace locus::tools::ipin
