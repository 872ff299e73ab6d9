#pragma once
// The online side of a match: one mean RSS per (type, bssid).
#include <string>
#include <vector>

#include "locus/radio_map.hpp"

namespace locus::match {

struct QueryAp {
    std::string type = "wifi";
    std::string bssid;  // normalised (normalise_bssid)
    double rss = 0.0;   // mean over the online scans, dBm
};

struct Query {
    std::vector<QueryAp> aps;  // one entry per (type, bssid), first-seen order

    // Averages several online scans per AP (SPEC §4: the seed takes 5). Readings outside
    // [kMinRss, kMaxRss] are bad samples and are dropped; BSSIDs are normalised.
    static Query from_scans(const std::vector<Scan>& scans);
    // Already-averaged input ("measurements" in the API); duplicates are averaged.
    static Query from_means(const std::vector<Reading>& means);
};

}  // namespace locus::match
