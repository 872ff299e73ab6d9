#pragma once
// What a track holds: fused fixes; and what a thin client posts instead: PDR steps, its
// barometer's pressure and its GNSS receiver's fixes.
#include <cstdint>
#include <optional>

namespace locus::tracks {

struct Fix {
    double t = 0;  // Unix seconds, the phone's clock
    std::int64_t floor_id = 0;
    double x = 0, y = 0, accuracy_m = 0;
    std::optional<double> heading_deg;  // clockwise from the floor's +y axis
};

struct Step {
    double t = 0;
    double length_m = 0;
    double heading_deg = 0;  // clockwise from the floor's +y axis, as client-lib's PDR
};

// A barometer sample: the phone's air pressure, for the barometric floor (docs/tracks.md).
struct Pressure {
    double t = 0;
    double hpa = 0;  // hectopascal (= mbar)
};

// A GNSS fix as the receiver gives it: WGS84, no floor (the track's filter takes it on its
// current floor, through that floor's georeference: docs/tracks.md).
struct Gnss {
    double t = 0;
    double lat = 0, lon = 0;  // degrees
    double accuracy_m = 0;    // the receiver's own, its 68 % radius
};

}  // namespace locus::tracks
