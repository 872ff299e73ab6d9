#include "tracks/thin_client.hpp"

#include <algorithm>
#include <string>
#include <tuple>

#include "tracks/radio_fix.hpp"

namespace locus::tracks {

namespace {

bool by_time(const Fix& a, const Fix& b) { return a.t < b.t; }

// A scan on a track fused by a Kalman method, ranged as POST /v1/maps/{id}/localize ranges it
// (kalman_trilateration: trilateration, kalman_ranging and ekf_ranging: multilateration, the
// default options), the ranging fix carried for its covariance. ekf_ranging also carries the
// readings of known transmitters, its measurements, and takes a scan that cannot be ranged as
// readings alone: refused only if the filter has not started (ThinFusion::run, the same error).
RadioFix ranged_scan_fix(ScanLocalizer& localizer, std::int64_t map_id, FusionMethod method, const TimedScan& scan) {
    const bool ekf = method == FusionMethod::ekf_ranging;
    RangedScan ranged = localizer.range(map_id, scan, method != FusionMethod::kalman_trilateration, ekf);
    RadioFix f;
    if (ranged.fix) {
        f = ranged_fix(scan.t, ranged.fix->first, ranged.fix->second);
    } else {
        if (!ekf) throw CannotFuse(ranged.refused.first, ranged.refused.second);
        f.t = scan.t;
        f.unplaced = {ranged.refused.first,
                      ranged.refused.second + "; ekf_ranging starts at a ranged scan (or a posted fix), then takes scans hearing even one or two"};
    }
    f.readings = std::move(ranged.readings);
    return f;
}

// The floors' georeferences, for the run's GNSS fixes.
class RunGeo : public RunSources {
public:
    explicit RunGeo(ScanLocalizer& localizer) : localizer_(localizer) {}
    std::shared_ptr<const geo::FloorToEarth> georeference(std::int64_t floor_id) override { return localizer_.georeference(floor_id); }

private:
    ScanLocalizer& localizer_;
};

}  // namespace

StepsDone post_steps(Service& svc, std::int64_t id, const StepsInput& in, ScanLocalizer& localizer) {
    StepsDone done;
    std::vector<RadioFix> radio(in.fixes.begin(), in.fixes.end());
    const auto track = svc.info(id);
    // An ekf_ranging filter (re)started by this request, even by steps alone (resumed at the
    // latest stored fix), takes its floor's transmitters as anchors; a Kalman track ranges its
    // scans on them; the particle filters take the radio map's match.
    std::shared_ptr<const FloorAnchors> anchors;
    if (track.fusion == FusionMethod::ekf_ranging && track.state == State::live) anchors = localizer.anchors(track.map_id);
    for (const auto& scan : in.scans) {
        if (ranges_scans(track.fusion)) {
            radio.push_back(ranged_scan_fix(localizer, track.map_id, track.fusion, scan));
        } else {
            const MatchedScan m = localizer.match(track.map_id, scan);
            radio.emplace_back(matched_fix(scan.t, m.floor_id, m.at, m.spread));
        }
        if (!radio.back().unplaced) done.scan_fixes.push_back(radio.back());
    }
    if (!in.scans.empty()) std::stable_sort(radio.begin(), radio.end(), by_time);
    std::vector<Fix> placed;
    for (const auto& r : radio)
        if (!r.unplaced) placed.push_back(r);
    if (const auto floor = svc.misplaced_floor(id, placed))
        throw ForeignFloor("floor " + std::to_string(*floor) + " is not a floor of track " + std::to_string(id) + "'s map");
    RunGeo geo(localizer);
    try {
        std::tie(done.posted, done.fused) = svc.post_raw(id, in.steps, radio, in.pressure, in.gnss, std::move(anchors), &geo);
    } catch (const CannotFuse&) {
        throw;
    } catch (const std::invalid_argument& e) {
        throw CannotFuse("cannot_fuse", e.what());
    }
    return done;
}

}  // namespace locus::tracks
