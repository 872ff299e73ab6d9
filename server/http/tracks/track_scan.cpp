// Eigen first: cpp-httplib (through api_error.hpp) pulls in <resolv.h>, whose `_res` macro breaks Eigen.
#include "locus/motion/fusion/kalman.hpp"

#include "http/tracks/track_scan.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "http/api_error.hpp"
#include "http/localize/localize_request.hpp"
#include "locus/match/localize.hpp"
#include "locus/match/workspace.hpp"

namespace locus::http {

tracks::Fix scan_fix(const localize::Snapshot& snapshot, double t, const Scan& readings, const std::string& where) {
    thread_local match::Workspace workspace;  // as answer(): the HTTP worker owns it
    LocalizeRequest request;                   // no algorithm, no options: the radio map's defaults
    request.query = match::Query::from_scans({readings});
    if (request.query.aps.empty()) throw invalid_field("'" + where + ".readings' holds no reading");
    const auto setting = resolve(request, snapshot.defaults);
    const auto result = match::localize(snapshot.index, request.query, setting.algorithm, setting.options, workspace);
    if (!result) throw ApiError(422, "no_match", "'" + where + "': no reference point of the track's map shares an access point with the scan");
    std::vector<Point> spread;
    for (const auto& c : result->candidates) {
        if (static_cast<int>(spread.size()) >= std::max(1, setting.options.k)) break;
        spread.push_back(c.at);
    }
    if (spread.empty()) spread.push_back(result->at);
    const Eigen::Matrix2d cov = fusion::fix_covariance(spread, {}, kScanFixFloorM);
    tracks::Fix f;
    f.t = t;
    f.floor_id = result->floor_id;
    f.x = result->at.x;
    f.y = result->at.y;
    f.accuracy_m = std::sqrt(cov.trace() / 2.0);  // the σ per axis of an isotropic fix with this spread
    return f;
}

}  // namespace locus::http
