#pragma once
// The online side of a match: one mean RSS per (type, bssid).
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "locus/radio_map.hpp"

namespace locus::match {

struct QueryAp {
    std::string type = "wifi";
    std::string bssid;  // normalised (a Bssid's text)
    double rss = 0.0;   // mean over the online scans, dBm
    // std::hash<std::string_view> of bssid, set by from_scans/from_means: the query hashes
    // each AP once, for its duplicate check and for the index lookup (Index::ap_of).
    std::size_t bssid_hash = 0;
};

// A reading that does not own its text, for a caller that still holds it (the server's
// request parser reads views into the body and copies nothing before the query).
struct ReadingView {
    std::string_view type = "wifi";
    std::string_view bssid;  // raw text from the wire, normalised by the query
    double rss = 0.0;
    bool normalised = false;  // bssid is already a Bssid's text
};

struct Query {
    std::vector<QueryAp> aps;  // one entry per (type, bssid), first-seen order

    // Averages several online scans per AP (docs/spec.md §4.1: nominally 5). Readings outside
    // [kMinRss, kMaxRss] are bad samples and are dropped; BSSIDs are normalised.
    static Query from_scans(const std::vector<Scan>& scans);
    // Already-averaged input ("measurements" in the API); duplicates are averaged.
    static Query from_means(const std::vector<Reading>& means);
    static Query from_means(std::span<const ReadingView> means);
};

}  // namespace locus::match
