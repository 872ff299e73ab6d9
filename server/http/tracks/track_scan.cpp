// Eigen first: cpp-httplib (through the headers below) pulls in <resolv.h>, whose `_res` macro breaks Eigen.
#include "http/tracks/track_scan.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "http/api_error.hpp"
#include "http/localize/localize_request.hpp"
#include "http/tracks/track_anchors.hpp"
#include "locus/match/localize.hpp"
#include "locus/match/workspace.hpp"
#include "tracks/radio_fix.hpp"

namespace locus::http {

const KnownTransmitters& MapScans::known(std::int64_t map_id) {
    // Every floor's of the map, at the phone height a ranging localize assumes by default.
    if (!known_) known_ = known_transmitters(store_, transmitters_, true, map_id, RangingRequest{}.phone_height);
    return *known_;
}

std::shared_ptr<const tracks::FloorAnchors> MapScans::anchors(std::int64_t map_id) { return floor_anchors(known(map_id)); }

namespace {

// The fingerprint an answer placed a scan at: its RPs' mean RSS, AP by AP (the mean over those
// of them that store it), over the query's APs, which is all match::DeviceOffset compares.
match::Fingerprint placed_at(const match::Index& index, const match::Query& query, const std::vector<long long>& rp_ids) {
    match::Fingerprint out;
    for (const match::QueryAp& ap : query.aps) {
        const long a = index.ap_of(ap.type, ap.bssid, ap.bssid_hash);
        if (a < 0) continue;
        const match::PostingList list = index.postings(static_cast<std::size_t>(a));
        double sum = 0.0;
        int n = 0;
        for (std::size_t k = 0; k < list.size(); ++k) {
            if (std::find(rp_ids.begin(), rp_ids.end(), index.rp(list.rp[k]).id) == rp_ids.end()) continue;
            sum += list.mean[k];
            ++n;
        }
        if (n > 0) out[ap.bssid] = sum / n;
    }
    return out;
}

}  // namespace

tracks::MatchedScan MapScans::match(std::int64_t map_id, const tracks::TimedScan& scan, std::optional<double> rss_offset_db) {
    if (!snapshot_) snapshot_ = localizer_.lookup(localize::Service::Scope::map, map_id);
    thread_local match::Workspace workspace;  // as answer(): the HTTP worker owns it
    LocalizeRequest request;                   // no algorithm, no options: the radio map's defaults
    Scan shifted = scan.readings;
    if (rss_offset_db)
        for (Reading& r : shifted) r.rss += *rss_offset_db;
    request.query = match::Query::from_scans({shifted});
    if (request.query.aps.empty()) throw invalid_field("'" + scan.where + ".readings' holds no reading");
    const auto setting = resolve(request, snapshot_->defaults);
    const auto result = match::localize(snapshot_->index, request.query, setting.algorithm, setting.options, workspace);
    if (!result) throw ApiError(422, "no_match", "'" + scan.where + "': no reference point of the track's map shares an access point with the scan");
    tracks::MatchedScan out{result->floor_id, result->at, tracks::candidate_spread(*result, setting.options.k), {}};
    if (rss_offset_db) out.placed_at = placed_at(snapshot_->index, request.query, result->rp_ids);
    return out;
}

tracks::RangedScan MapScans::range(std::int64_t map_id, const tracks::TimedScan& scan, bool multilateration, bool with_readings) {
    const KnownTransmitters& k = known(map_id);  // read once for the batch
    RangingRequest request;
    request.multilateration = multilateration;
    request.query = match::Query::from_scans({scan.readings});
    if (request.query.aps.empty()) throw invalid_field("'" + scan.where + ".readings' holds no reading");
    tracks::RangedScan out;
    if (with_readings) out.readings = anchor_readings(k, request.query, scan.t);
    try {
        const Ranged ranged = range_scan(k, request);
        out.fix = {ranged.floor_id, ranged.fix};
    } catch (const ApiError& e) {
        const std::string message = "'" + scan.where + "': " + e.what();
        if (e.status != 422) throw ApiError(e.status, e.code, message);
        out.refused = {e.code, message};
    }
    return out;
}

}  // namespace locus::http
