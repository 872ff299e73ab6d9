#pragma once
// Small hand-made radio maps for the matcher unit tests.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "locus/match/index.hpp"
#include "locus/match/localize.hpp"

namespace locus::match::testing {

inline Measurement m(const std::string& bssid, double mean, double variance = 1.0, std::int64_t count = 10) {
    return Measurement{"wifi", bssid, RssStats{mean, variance, count}};
}

// An RP surveyed with 10 scans.
inline IndexedRp rp(long long id, Point at, std::vector<Measurement> ms, long long floor = 1, long long building = 1) {
    IndexedRp r;
    r.rp.id = id;
    r.rp.at = at;
    r.rp.scans = 10;
    r.rp.measurements = std::move(ms);
    r.floor_id = floor;
    r.building_id = building;
    return r;
}

// match::localize with default options at hand, every call reusing one workspace as a
// worker thread does, so a test that queries several maps also runs them through one
// workspace of changing size.
inline std::optional<Result> localize(const Index& index, const Query& query, Algorithm algorithm,
                                      const Options& options = {}) {
    static Workspace workspace;
    return match::localize(index, query, algorithm, options, workspace);
}

}  // namespace locus::match::testing
