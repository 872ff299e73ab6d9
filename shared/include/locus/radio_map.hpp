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

// An access point's or beacon's identifier in its one normal form: trimmed, ASCII
// lower-case, a MAC written aa-bb-cc-dd-ee-ff the same as aa:bb:cc:dd:ee:ff; BLE ids and other
// free strings are only trimmed and lower-cased. Every Bssid is normalised, because making one
// from text normalises it: readers, the store, the index and the matchers then compare plain
// strings and never normalise again. Construction from text is implicit so that a reader's
// `m.bssid = field` is the edge where normalisation happens (it costs one pass over the text).
class Bssid {
public:
    Bssid() = default;
    Bssid(std::string_view raw);  // implicit on purpose, see above
    Bssid(const char* raw) : Bssid(std::string_view(raw)) {}
    Bssid(const std::string& raw) : Bssid(std::string_view(raw)) {}
    // Text that was a Bssid's when it was written (the store reading back its own rows):
    // taken as it is, so a read does not normalise again.
    static Bssid stored(std::string normal_form) {
        Bssid b;
        b.text_ = std::move(normal_form);
        return b;
    }

    const std::string& str() const { return text_; }
    operator const std::string&() const { return text_; }
    bool empty() const { return text_.empty(); }

    friend bool operator==(const Bssid&, const Bssid&) = default;
    friend auto operator<=>(const Bssid&, const Bssid&) = default;

private:
    std::string text_;
};

// `raw` without the white space (ASCII: space, \t \n \v \f \r) around it, as a Bssid
// trims it.
std::string_view trim_bssid(std::string_view raw);

struct Measurement {
    std::string type = "wifi";  // "wifi" or "ble"
    Bssid bssid;
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
    Bssid bssid;
    double rss = 0.0;
};
using Scan = std::vector<Reading>;

// Per (type, bssid) aggregate of several scans, in first-seen order.
std::vector<Measurement> aggregate_scans(const std::vector<Scan>& scans);

// Combines the aggregates of one (type, bssid) into one (RssStats::merge), in first-seen
// order: what merging them one after another into a stored RP gives. Returns false, leaving `ms` unspecified, when an AP's counts add up past
// kMaxCount; `overflow` then names it.
bool combine_aggregates(std::vector<Measurement>& ms, std::string* overflow = nullptr);

}  // namespace locus
