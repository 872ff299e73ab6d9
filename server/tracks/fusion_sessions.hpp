#pragma once
// The thin clients' filters (docs/tracks.md, POST /v1/tracks/{id}/steps): one ThinFusion per
// track this server has fused steps for, and the floors' walkable areas they walk on.
//
// A filter runs on a copy of the held one (a `Run`), and the copy replaces it only once the
// fused fixes are stored (`Run::keep`), so a refused or failed store leaves the track's filter
// as it was. One mutex covers every session and is held through a whole run: runs of different
// tracks wait for one another, which keeps the plans' cache simple; a run costs what the
// filter costs (tracks/fusion.hpp), a plan's walkable area is built once per floor and change.
// Lock order: this mutex before the repository's and the cache's.
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/motion/fusion/walkable.hpp"
#include "store/store.hpp"
#include "tracks/fix.hpp"
#include "tracks/fusion_method.hpp"
#include "tracks/fusion_options.hpp"
#include "tracks/run_sources.hpp"

namespace locus::tracks {

// tracks/fusion.hpp: not included here, so that this header (and service.hpp) stays free of
// Eigen, which cpp-httplib's <resolv.h> breaks when it comes first.
class ThinFusion;
struct RadioFix;
struct FloorAnchors;
struct BaroLevel;
struct Crossing;

class FusionSessions {
public:
    explicit FusionSessions(store::Store& store) : store_(store) {}

    // One filter run of track `id`, holding that track's own lock from its start to its end:
    // one track's runs take turns (each continues the filter the one before kept), different
    // tracks' run in parallel, each on its request's thread. The sessions' lock guards only
    // the maps below, for a lookup or an insert (and a floor's first Walkable, built once).
    class Run {
    public:
        // The filter's fixes for these inputs: the held filter continued, or (none held, or
        // the track's stored fixes have passed it: a restart, fixes posted directly, another
        // server's steps) one started afresh at `latest`, seeded with the track's id so a
        // track's fused fixes are reproducible. `sources` (may be null: no georeference, no
        // scans) gives the floors' georeferences and walk_pf's scans, localized with the
        // filter's RSS offset once the filter to run is known (its radio fixes join `radio`).
        std::vector<Fix> run(FusionMethod method, const FusionOptions& options, const std::optional<Fix>& latest,
                             const std::vector<Step>& steps, const std::vector<RadioFix>& radio,
                             const std::vector<Pressure>& pressure, const std::vector<Gnss>& gnss,
                             std::shared_ptr<const FloorAnchors> anchors, RunSources* sources);
        // The run's fixes are stored: its filter is the track's from now on.
        void keep();

    private:
        friend class FusionSessions;
        Run(FusionSessions& sessions, std::int64_t id) : sessions_(sessions), track_(sessions.track_lock(id)), lock_(*track_), id_(id) {}
        FusionSessions& sessions_;
        std::shared_ptr<std::mutex> track_;
        std::unique_lock<std::mutex> lock_;
        std::int64_t id_;
        std::shared_ptr<ThinFusion> next_;
    };

    // Takes track `id`'s lock: call with no other tracks lock held.
    Run begin(std::int64_t id) { return Run(*this, id); }
    // The tracks ended, evicted or deleted: their filters go.
    void forget(const std::vector<std::int64_t>& ids);
    // A floor's plan changed (or the floor did): its walkable area is built again when next used.
    void floor_changed(std::int64_t floor_id);
    // Every floor may have changed (a map deleted, another server's "everything changed").
    void all_floors_changed();

private:
    std::shared_ptr<const fusion::Walkable> walkable_of(std::int64_t floor_id);  // takes mu_
    std::shared_ptr<std::mutex> track_lock(std::int64_t id);                     // takes mu_
    // The floors of floor_id's building that have an elevation_m, read from the store each time
    // (a filter asks once per building it walks in): a row per floor, and one query per floor
    // for whether it has a radio map.
    std::vector<BaroLevel> levels_of(std::int64_t floor_id);
    // The stairs or lift nearest `at` on floor `from`'s plan that leads to floor `to` (linked
    // both ways, as routes take them): where it stands on each floor. Reads both plans.
    std::optional<Crossing> crossing(std::int64_t from, std::int64_t to, Point at);

    store::Store& store_;
    std::mutex mu_;
    std::unordered_map<std::int64_t, std::shared_ptr<ThinFusion>> fusions_;
    // Each track's run lock, made at its first run and dropped with its filter (forget); a run
    // holds its own reference, so one in flight outlives a forget.
    std::unordered_map<std::int64_t, std::shared_ptr<std::mutex>> track_locks_;
    std::unordered_map<std::int64_t, std::shared_ptr<const fusion::Walkable>> walkables_;  // by floor
};

}  // namespace locus::tracks
