#include "tracks/map_scans.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "locus/match/localize.hpp"
#include "locus/match/workspace.hpp"
#include "tracks/radio_fix.hpp"
#include "tracks/track_anchors.hpp"
#include "transmitters/refused.hpp"

namespace locus::tracks {

const transmitters::KnownTransmitters& MapScans::known(std::int64_t map_id) {
    // Every floor's of the map, at the phone height a ranging localize assumes by default.
    if (!known_)
        known_ = transmitters::known_transmitters(sources_.store, sources_.transmitters, true, map_id,
                                                  transmitters::RangingRequest{}.phone_height);
    return *known_;
}

std::shared_ptr<const FloorAnchors> MapScans::anchors(std::int64_t map_id) { return floor_anchors(known(map_id)); }

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

CannotFuse no_reading(const TimedScan& scan) { return CannotFuse("invalid_field", "'" + scan.where + ".readings' holds no reading"); }

}  // namespace

MatchedScan MapScans::match(std::int64_t map_id, const TimedScan& scan, std::optional<double> rss_offset_db,
                            std::optional<match::Near> near) {
    if (!snapshot_) snapshot_ = sources_.localizer.lookup(localize::Service::Scope::map, map_id);
    thread_local match::Workspace workspace;  // as the localize endpoint's: the HTTP worker owns it
    Scan shifted = scan.readings;
    if (rss_offset_db)
        for (Reading& r : shifted) r.rss += *rss_offset_db;
    const match::Query query = match::Query::from_scans({shifted});
    if (query.aps.empty()) throw no_reading(scan);
    // A request naming no algorithm and no options: the radio map's stored defaults.
    const match::Setting& setting = snapshot_->defaults;
    std::optional<match::Result> result;
    if (near) {
        match::Options options = setting.options;
        options.near = near;
        result = match::localize(snapshot_->index, query, setting.algorithm, options, workspace);
    }
    const bool fell_back = near && !result;
    if (!result) result = match::localize(snapshot_->index, query, setting.algorithm, setting.options, workspace);
    if (!result)
        throw CannotFuse("no_match", "'" + scan.where + "': no reference point of the track's map shares an access point with the scan");
    MatchedScan out{result->floor_id, result->at, candidate_spread(*result, setting.options.k), {}, fell_back};
    if (rss_offset_db) out.placed_at = placed_at(snapshot_->index, query, result->rp_ids);
    return out;
}

std::optional<PlacedBeacon> MapScans::beacon(std::int64_t map_id, const Reading& reading) {
    if (reading.type != "ble") return std::nullopt;
    const transmitters::KnownTransmitters& k = known(map_id);
    const auto it = k.by_key.find(transmitters::transmitter_key(reading.type, reading.bssid.str()));
    if (it == k.by_key.end()) return std::nullopt;
    return PlacedBeacon{it->second.floor_id, it->second.tx.at};
}

RangedScan MapScans::range(std::int64_t map_id, const TimedScan& scan, bool multilateration, bool with_readings) {
    const transmitters::KnownTransmitters& k = known(map_id);  // read once for the batch
    transmitters::RangingRequest request;
    request.multilateration = multilateration;
    request.query = match::Query::from_scans({scan.readings});
    if (request.query.aps.empty()) throw no_reading(scan);
    RangedScan out;
    if (with_readings) out.readings = anchor_readings(k, request.query, scan.t);
    try {
        const transmitters::Ranged ranged = transmitters::range_scan(k, request);
        out.fix = {ranged.floor_id, ranged.fix};
    } catch (const transmitters::Refused& e) {
        out.refused = {e.code, "'" + scan.where + "': " + e.what()};
    }
    return out;
}

StepsDone post_steps(Service& svc, std::int64_t id, const StepsInput& in, const MapSources& sources) {
    MapScans scans(sources);
    return post_steps(svc, id, in, scans);
}

}  // namespace locus::tracks
