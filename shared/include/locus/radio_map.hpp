#pragma once
// Radio-map value types shared by the server, the matchers and the tools.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/rss_stats.hpp"

namespace locus {

inline constexpr double kMinRss = -120.0;
inline constexpr double kMaxRss = 0.0;

bool valid_rss(double rss);  // finite and within [kMinRss, kMaxRss]

// Lower-cases a BSSID; MACs written with '-' become ':' separated (aa:bb:cc:dd:ee:ff).
// BLE ids and other free strings are only lower-cased and trimmed.
std::string normalise_bssid(std::string_view raw);
// `raw` without the white space (ASCII: space, \t \n \v \f \r) around it, as
// normalise_bssid trims it.
std::string_view trim_bssid(std::string_view raw);

struct Measurement {
    std::string type = "wifi";  // "wifi" or "ble"
    std::string bssid;
    RssStats stats;
};

struct ReferencePoint {
    long long id = 0;
    std::string name;
    Point at;
    std::int64_t scans = 0;  // raw scans taken here: the denominator of an AP's detection rate
    std::vector<Measurement> measurements;
};

struct Reading {
    std::string type = "wifi";
    std::string bssid;
    double rss = 0.0;
};
using Scan = std::vector<Reading>;

// Per (type, bssid) aggregate of several scans, in first-seen order.
std::vector<Measurement> aggregate_scans(const std::vector<Scan>& scans);

// Combines the aggregates of one (type, bssid) into one (RssStats::merge), in first-seen
// order: what merging them one after another into a stored RP gives. BSSIDs must already be
// normalised. Returns false, leaving `ms` unspecified, when an AP's counts add up past
// kMaxCount; `overflow` then names it.
bool combine_aggregates(std::vector<Measurement>& ms, std::string* overflow = nullptr);

}  // namespace locus
