#pragma once
// A phone's RSS offset, learnt online from its own scans, with no table of phones. Phones of
// different makes read the same AP several dB apart (the IPIN 2023 walks: a Galaxy S7 about
// 5.7 dB below an A5, docs/ipin-import.md), and a radio map surveyed with one phone then places
// another's scans where the signal is that much weaker. The estimator compares each scan with
// the fingerprint the matcher placed it at (the answer's RPs' mean RSS per AP): the median over
// their shared APs of (fingerprint − reading) is that scan's look at the offset, and the
// estimate is the mean of the looks, shrunk towards 0 dB by `prior_scans` looks of 0 (so a walk's
// first scans move it little), clipped to ±max_abs_db. Scans sent with the estimate added are
// placed better, and their looks then measure what is left: the estimate settles where the
// shifted scans fit their matches on average (the self-consistent calibration of Tsui et al.,
// "Unsupervised learning for solving RSS hardware variance problem in WiFi localization",
// Mobile Networks and Applications 14(5), 2009, with the matcher's answer for the location).
// Causal: the estimate after n scans uses only those n.
//
// Cost: add() O(r log r + f) for r readings and a fingerprint of f APs (a hash of the
// fingerprint's APs); memory O(1) beyond the caller's.
#include <string>
#include <unordered_map>

#include "locus/radio_map.hpp"

namespace locus::match {

struct DeviceOffsetConfig {
    int min_shared_aps = 3;    // a scan sharing fewer APs with its fingerprint is no look
    double prior_scans = 5.0;  // looks of 0 dB the estimate starts from
    double max_abs_db = 15.0;  // no phone is this far off; a larger estimate is a mismatch
};

// Mean RSS (dBm) by AP (Bssid::str()): the fingerprint a scan was placed at.
using Fingerprint = std::unordered_map<std::string, double>;

class DeviceOffset {
public:
    // Throws std::invalid_argument on min_shared_aps < 1, prior_scans < 0 or max_abs_db ≤ 0.
    explicit DeviceOffset(const DeviceOffsetConfig& config = {});

    // A scan as the phone read it (no offset added) and the fingerprint its answer is built
    // from. Returns whether it counted (enough shared APs).
    bool add(const Scan& scan, const Fingerprint& placed_at);
    // What to add to this phone's readings (dB); 0 before any look.
    double offset_db() const;
    int looks() const { return looks_; }

private:
    DeviceOffsetConfig config_;
    double sum_ = 0.0;
    int looks_ = 0;
};

}  // namespace locus::match
