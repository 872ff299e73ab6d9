#pragma once
// Distance between two phones from the RSSI one hears of the other (Bonjorn López 2016, Wi-Fi Direct or
// BLE between the phones). The model is the same log-distance model as for fixed transmitters
// (locus/ranging/path_loss.hpp); only its calibration differs, so only the constants live here.
#include <span>

#include "locus/ranging/path_loss.hpp"

namespace locus::relative {

// Defaults for two handsets in hand at 1 m; calibrate per pair where possible. Phone radios
// are weaker and held lower than ceiling beacons, hence the lower power at 1 m and a steeper
// exponent than free space (bodies in the way).
struct PhoneLink {
    ranging::PathLoss model{-45.0, 2.5};
};

// The distance (m) for one RSSI (dBm).
double phone_distance(const PhoneLink& link, double rssi_dbm);
// The distance for a short window of readings: their mean in dB first, since the shadowing is
// (roughly) Gaussian in dB, not in metres. Requires at least one reading.
double phone_distance(const PhoneLink& link, std::span<const double> rssi_dbm);

}  // namespace locus::relative
