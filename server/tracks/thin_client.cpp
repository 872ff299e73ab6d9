#include "tracks/thin_client.hpp"

#include <algorithm>
#include <string>
#include <tuple>

#include "locus/motion/fusion/beacon.hpp"
#include "tracks/radio_fix.hpp"
#include "tracks/scan_memory.hpp"

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

// A scan's subarea round the filter's estimate (tracks/scan_area.hpp); a scan no RP there
// shares an AP with is matched on the whole map.
std::optional<match::Near> subarea(const std::optional<Fix>& estimate, double t) {
    if (!estimate) return std::nullopt;
    return subarea_round(*estimate, t);
}

// walk_pf's scans, localized during the filter's run (Service::post_raw): each matched within
// the subarea round the filter's estimate before the batch, shifted by the phone's offset learnt
// from the scans before it, in time order, then teaching it with the fingerprint it was placed
// at, as `locus eval ipin` does (tools/commands/eval_ipin.cpp); and
// its strong readings of the map's beacons, fixes at them (after the scan's own fix at equal t,
// as the evaluation orders them).
class RunScans : public RunSources {
public:
    RunScans(Service& svc, std::int64_t id, std::int64_t map_id, const std::vector<TimedScan>* scans, ScanLocalizer& localizer, bool use_subarea)
        : svc_(svc), id_(id), map_id_(map_id), scans_(scans), localizer_(localizer), use_subarea_(use_subarea) {}

    std::shared_ptr<const geo::FloorToEarth> georeference(std::int64_t floor_id) override { return localizer_.georeference(floor_id); }

    std::vector<Fix> scans(ScanMemory& memory, std::optional<double> done_t, const std::optional<Fix>& estimate) override {
        std::vector<Fix> out;
        scan_fixes.clear();
        scan_areas.clear();
        if (!scans_) return out;
        for (const TimedScan& scan : *scans_) {
            const bool teaches = !done_t || scan.t > *done_t;
            std::vector<Fix> near;
            bool ble_only = true;
            for (const Reading& r : scan.readings) {
                ble_only = ble_only && r.type == "ble";
                // A beacon is a measurement for a running filter on its floor, as the evaluation's
                // trackers take it: never what starts a track or moves it to another floor (a
                // strong reading through a stairwell: twice in ~300 on the IPIN walks).
                const auto b = estimate ? localizer_.beacon(map_id_, r) : std::nullopt;
                if (b && b->floor_id == estimate->floor_id && r.rss >= fusion::kBeaconMinRssDbm && teaches &&
                    memory.beacons.take(r.bssid.str(), scan.t))
                    near.push_back({scan.t, b->floor_id, b->at.x, b->at.y, fusion::kBeaconSigmaM, std::nullopt});
            }
            try {
                const auto area = use_subarea_ ? subarea(estimate, scan.t) : std::nullopt;
                const MatchedScan m = localizer_.match(map_id_, scan, memory.offset.offset_db(), area);
                if (teaches) memory.offset.add(scan.readings, m.placed_at);
                out.push_back(matched_fix(scan.t, m.floor_id, m.at, m.spread));
                scan_fixes.push_back(out.back());
                scan_areas.push_back({area, m.fell_back});
            } catch (const CannotFuse& e) {
                // A BLE scan is a proximity scan first: the radio map need not hold its beacons.
                if (!(ble_only && e.code == "no_match")) throw;
            }
            out.insert(out.end(), near.begin(), near.end());
        }
        if (const auto floor = svc_.misplaced_floor(id_, out))
            throw ForeignFloor("floor " + std::to_string(*floor) + " is not a floor of track " + std::to_string(id_) + "'s map");
        offset_db = memory.offset.offset_db();
        return out;
    }

    std::vector<Fix> scan_fixes;  // the matched ones, not the beacons'
    std::vector<ScanArea> scan_areas;
    std::optional<double> offset_db;

private:
    Service& svc_;
    std::int64_t id_, map_id_;
    const std::vector<TimedScan>* scans_;  // null: the scans went the other way (not walk_pf)
    ScanLocalizer& localizer_;
    bool use_subarea_;
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
    const bool learns_offset = track.fusion == FusionMethod::walk_pf;
    RunScans run_scans(svc, id, track.map_id, learns_offset ? &in.scans : nullptr, localizer, track.fusion_options.subarea.value_or(true));
    // walk_pf's scans are localized in the run (RunScans), with the offset its filter learnt.
    const std::vector<TimedScan> none;
    for (const TimedScan& scan : learns_offset ? none : in.scans) {
        if (ranges_scans(track.fusion)) {
            radio.push_back(ranged_scan_fix(localizer, track.map_id, track.fusion, scan));
        } else {
            const MatchedScan m = localizer.match(track.map_id, scan, std::nullopt);
            radio.emplace_back(matched_fix(scan.t, m.floor_id, m.at, m.spread));
        }
        if (!radio.back().unplaced) done.scan_fixes.push_back(radio.back()), done.scan_areas.emplace_back();
    }
    if (!in.scans.empty()) std::stable_sort(radio.begin(), radio.end(), by_time);
    std::vector<Fix> placed;
    for (const auto& r : radio)
        if (!r.unplaced) placed.push_back(r);
    if (const auto floor = svc.misplaced_floor(id, placed))
        throw ForeignFloor("floor " + std::to_string(*floor) + " is not a floor of track " + std::to_string(id) + "'s map");
    try {
        std::tie(done.posted, done.fused) = svc.post_raw(id, in.steps, radio, in.pressure, in.gnss, std::move(anchors), &run_scans);
    } catch (const CannotFuse&) {
        throw;
    } catch (const ForeignFloor&) {
        throw;
    } catch (const std::invalid_argument& e) {
        throw CannotFuse("cannot_fuse", e.what());
    }
    if (learns_offset) {
        done.scan_fixes = std::move(run_scans.scan_fixes);
        done.scan_areas = std::move(run_scans.scan_areas);
        done.rss_offset_db = run_scans.offset_db;
    }
    return done;
}

}  // namespace locus::tracks
