#pragma once
// A BLE beacon heard strongly as a walk filter's position measurement: "the phone is a few
// metres from this beacon, on its floor". One place for the settings `locus eval ipin`'s
// trackers (tools/ipin_track.hpp) and the server's live tracks (server/tracks/thin_client.hpp)
// both run, chosen on the IPIN 2023 walks (docs/results.md, "BLE beacons"): a reading at
// -65 dBm or more was heard within 6 m of its beacon at p75 (median 3 m) and from another floor
// twice in ~300; at -65 to -70 dBm the p75 is 9 m, and weaker readings say little (median
// 12-24 m). A walker passing a beacon hears it for seconds, and those readings are one look:
// one reading per beacon per kBeaconMinIntervalS counts.
//
// Cost: BeaconGate holds one time per beacon heard; take() is a map lookup.
#include <map>
#include <string>

namespace locus::fusion {

inline constexpr double kBeaconMinRssDbm = -65.0;  // weaker readings are no measurement
inline constexpr double kBeaconSigmaM = 6.0;       // the measurement's σ, at the beacon
inline constexpr double kBeaconMinIntervalS = 2.0;

// Which readings of which beacons count: one per beacon (any key naming it) per interval.
class BeaconGate {
public:
    explicit BeaconGate(double min_interval_s = kBeaconMinIntervalS) : min_interval_s_(min_interval_s) {}
    // True when a reading of `beacon` at t counts (and then it is the one the interval runs from).
    bool take(const std::string& beacon, double t) {
        const auto it = last_.find(beacon);
        if (it != last_.end() && t - it->second < min_interval_s_) return false;
        last_[beacon] = t;
        return true;
    }

private:
    double min_interval_s_;
    std::map<std::string, double> last_;
};

}  // namespace locus::fusion
