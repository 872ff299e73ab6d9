#include "tuning/service.hpp"

#include <chrono>
#include <unordered_map>
#include <utility>

#include "store/kinds.hpp"

namespace locus::tuning {

namespace {

// A radio map's RPs as the matchers index them, read once (one consistent snapshot), and the
// level of each floor they are on, for the floor penalty.
struct Snapshot {
    std::vector<match::IndexedRp> rps;
    std::unordered_map<long long, long long> levels;
};

Snapshot snapshot_of(store::Store& store, std::int64_t radiomap_id) {
    Snapshot out;
    auto stored = store.rps_of_radiomap(radiomap_id);
    out.rps.reserve(stored.size());
    for (auto& s : stored) {
        if (!out.levels.count(s.floor_id))
            out.levels[s.floor_id] = store.get(store::kind("floors"), s.floor_id).fields.get<std::int64_t>("level");
        out.rps.push_back({std::move(s.rp), s.floor_id, s.building_id});
    }
    return out;
}

}  // namespace

// The radio map marked as being tuned for as long as the tune runs.
class Service::TuneGuard {
public:
    TuneGuard(Service& service, std::int64_t id) : service_(service), id_(id) {
        std::lock_guard lock(service_.mu_);
        if (!service_.tuning_.insert(id_).second)
            throw Running("radiomap " + std::to_string(id_) + " is being tuned already; try again when it is done");
    }
    ~TuneGuard() {
        std::lock_guard lock(service_.mu_);
        service_.tuning_.erase(id_);
    }
    TuneGuard(const TuneGuard&) = delete;
    TuneGuard& operator=(const TuneGuard&) = delete;

private:
    Service& service_;
    std::int64_t id_;
};

// One of the quality slots, for as long as the assessment runs.
class Service::QualitySlot {
public:
    explicit QualitySlot(Service& service) : service_(service) {
        std::lock_guard lock(service_.mu_);
        if (service_.quality_free_ == 0)
            throw Busy(std::to_string(service_.quality_at_once_) + " quality assessments are running already; retry in a second");
        --service_.quality_free_;
    }
    ~QualitySlot() {
        std::lock_guard lock(service_.mu_);
        ++service_.quality_free_;
    }
    QualitySlot(const QualitySlot&) = delete;
    QualitySlot& operator=(const QualitySlot&) = delete;

private:
    Service& service_;
};

Service::Service(store::Store& store, SettingsText text, std::size_t quality_at_once)
    : store_(store), text_(std::move(text)), quality_free_(quality_at_once), quality_at_once_(quality_at_once) {}

Quality Service::quality(std::int64_t radiomap_id, const match::TuneLimits& limits) {
    store_.get(store::kind("radiomaps"), radiomap_id);  // 404 before anything else
    // An unknown radio map costs nothing and is never busy.
    const QualitySlot slot(*this);
    Quality out;
    const auto stored = store_.settings_of_radiomap(radiomap_id);
    out.tuned = stored.has_value();
    out.setting = stored ? text_.read(stored->settings) : match::Setting{};
    Snapshot snap = snapshot_of(store_, radiomap_id);  // named, not bound: clang 14 lambdas cannot capture bindings
    out.report = match::held_out_errors(snap.rps, out.setting, [&snap](long long floor) { return snap.levels[floor]; }, limits);
    out.rps = std::move(snap.rps);
    return out;
}

Tuned Service::tune(std::int64_t radiomap_id, const match::TuneLimits& limits) {
    store_.get(store::kind("radiomaps"), radiomap_id);  // 404 before anything else
    const TuneGuard guard(*this, radiomap_id);
    const auto t0 = std::chrono::steady_clock::now();
    Snapshot snap = snapshot_of(store_, radiomap_id);  // named, not bound: clang 14 lambdas cannot capture bindings
    const auto grid = match::tune_grid();
    Tuned out;
    out.report = match::tune(snap.rps, grid, [&snap](long long floor) { return snap.levels[floor]; }, limits);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& best = out.report.rows[out.report.best];
    const store::RadiomapSettings settings{text_.write(best.setting), text_.write_table(out.report, out.seconds), {}};
    out.written = store_.put_radiomap_settings(radiomap_id, settings);
    return out;
}

}  // namespace locus::tuning
