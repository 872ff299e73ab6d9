// Eigen first (tracks/fusion.hpp): see tracks/fusion_sessions.hpp.
#include "tracks/fusion.hpp"
#include "tracks/fusion_sessions.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <variant>

namespace locus::tracks {

std::shared_ptr<const fusion::Walkable> FusionSessions::walkable_of(std::int64_t floor_id) {
    // Under the sessions' lock while a floor's first one is built (~0.1 s for 1,714 walls,
    // docs/results.md "Tracking cost"): the tracks on that floor wait for it instead of each
    // building its own.
    std::lock_guard lock(mu_);
    if (const auto w = walkables_.find(floor_id); w != walkables_.end()) return w->second;
    const auto stored = store_.plan_of_floor(floor_id);
    if (!stored) return nullptr;
    auto w = std::make_shared<const fusion::Walkable>(fusion::Walkable::from_plan(stored->plan));
    walkables_[floor_id] = w;
    return w;
}

std::vector<BaroLevel> FusionSessions::levels_of(std::int64_t floor_id) {
    std::vector<BaroLevel> out;
    try {
        const auto building = store_.get(store::kind("floors"), floor_id).parent_id;
        constexpr std::int64_t kPage = 500;
        for (std::int64_t offset = 0;; offset += kPage) {
            const auto page = store_.list(store::kind("floors"), building, kPage, offset);
            for (const auto& floor : page.items) {
                const auto e = floor.fields.values.find("elevation_m");
                if (e == floor.fields.values.end() || !std::holds_alternative<double>(e->second)) continue;
                const bool radio = store_.list(store::kind("radiomaps"), floor.id, 1, 0).total > 0;
                out.push_back({floor.id, std::get<double>(e->second), radio});
            }
            if (offset + kPage >= page.total) break;
        }
    } catch (const store::NotFound&) {
        return {};  // the floor went (deleted since the fix): no barometer
    }
    return out;
}

std::optional<Crossing> FusionSessions::crossing(std::int64_t from, std::int64_t to, Point at) {
    const auto here = store_.plan_of_floor(from);
    if (!here) return std::nullopt;
    const auto there = store_.plan_of_floor(to);
    if (!there) return std::nullopt;
    std::optional<Crossing> best;
    double best_d = 0.0;
    for (const auto& c : here->plan.connectors) {
        for (const auto& link : c.links) {
            if (link.floor_id != to) continue;
            const auto other = std::find_if(there->plan.connectors.begin(), there->plan.connectors.end(),
                                            [&](const plan::Connector& o) { return o.id == link.connector; });
            if (other == there->plan.connectors.end()) continue;
            const bool back = std::any_of(other->links.begin(), other->links.end(),
                                          [&](const plan::ConnectorLink& l) { return l.floor_id == from && l.connector == c.id; });
            const double d = std::hypot(c.at.x - at.x, c.at.y - at.y);
            if (back && (!best || d < best_d)) {
                best = Crossing{c.at, other->at};
                best_d = d;
            }
        }
    }
    return best;
}

std::vector<Fix> FusionSessions::Run::run(FusionMethod method, const FusionOptions& options, const std::optional<Fix>& latest,
                                          const std::vector<Step>& steps, const std::vector<RadioFix>& radio,
                                          const std::vector<Pressure>& pressure, const std::vector<Gnss>& gnss,
                                          std::shared_ptr<const FloorAnchors> anchors, RunSources* sources) {
    auto& held = sessions_.fusions_;
    const auto walkable_of = [this](std::int64_t floor_id) { return sessions_.walkable_of(floor_id); };
    struct Floors {
        FusionSessions& sessions;
        RunSources* sources;
        std::vector<BaroLevel> levels(std::int64_t floor_id) const { return sessions.levels_of(floor_id); }
        std::optional<Crossing> crossing(std::int64_t from, std::int64_t to, Point at) const { return sessions.crossing(from, to, at); }
        std::shared_ptr<const geo::FloorToEarth> georeference(std::int64_t floor_id) const {
            return sources ? sources->georeference(floor_id) : nullptr;
        }
    };
    std::shared_ptr<const ThinFusion> kept;
    {
        std::lock_guard lock(sessions_.mu_);
        if (const auto it = held.find(id_); it != held.end()) kept = it->second;
    }
    const bool continues = kept && (!latest || (kept->done_t() && latest->t <= *kept->done_t()));
    next_ = continues ? std::make_shared<ThinFusion>(*kept)
                      : std::make_shared<ThinFusion>(method, static_cast<std::uint64_t>(id_), options);
    next_->set_anchors(std::move(anchors));
    if (!continues && latest) next_->resume(*latest, walkable_of, bearing_of(Floors{sessions_, sources}, latest->floor_id));
    // The scans are localized only now: each with the offset this very filter has learnt.
    std::vector<RadioFix> merged;
    const std::vector<RadioFix>* all = &radio;
    if (sources) {
        std::vector<Fix> placed = sources->scans(next_->scan_memory(), next_->done_t(), next_->estimate());
        if (!placed.empty()) {
            merged = radio;
            for (const Fix& f : placed) merged.emplace_back(f);
            std::stable_sort(merged.begin(), merged.end(), [](const RadioFix& a, const RadioFix& b) { return a.t < b.t; });
            all = &merged;
        }
    }
    return next_->run(steps, *all, pressure, gnss, walkable_of, Floors{sessions_, sources});
}

void FusionSessions::Run::keep() {
    if (!next_) return;
    std::lock_guard lock(sessions_.mu_);
    // A track forgotten while this ran (ended, evicted, deleted) keeps no filter.
    const auto it = sessions_.track_locks_.find(id_);
    if (it != sessions_.track_locks_.end() && it->second == track_) sessions_.fusions_[id_] = std::move(next_);
}

std::shared_ptr<std::mutex> FusionSessions::track_lock(std::int64_t id) {
    std::lock_guard lock(mu_);
    auto& m = track_locks_[id];
    if (!m) m = std::make_shared<std::mutex>();
    return m;
}

void FusionSessions::forget(const std::vector<std::int64_t>& ids) {
    if (ids.empty()) return;
    std::lock_guard lock(mu_);
    for (const auto id : ids) {
        fusions_.erase(id);
        track_locks_.erase(id);
    }
}

void FusionSessions::floor_changed(std::int64_t floor_id) {
    std::lock_guard lock(mu_);
    walkables_.erase(floor_id);
}

void FusionSessions::all_floors_changed() {
    std::lock_guard lock(mu_);
    walkables_.clear();
}

}  // namespace locus::tracks
