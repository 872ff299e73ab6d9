// Eigen first (tracks/fusion.hpp): see tracks/fusion_sessions.hpp.
#include "tracks/fusion.hpp"
#include "tracks/fusion_sessions.hpp"

#include <utility>
#include <variant>

namespace locus::tracks {

std::shared_ptr<const fusion::Walkable> FusionSessions::walkable_of(std::int64_t floor_id) {
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

std::vector<Fix> FusionSessions::Run::run(FusionMethod method, const FusionOptions& options, const std::optional<Fix>& latest,
                                          const std::vector<Step>& steps, const std::vector<RadioFix>& radio,
                                          const std::vector<Pressure>& pressure, std::shared_ptr<const FloorAnchors> anchors) {
    auto& held = sessions_.fusions_;
    const auto walkable_of = [this](std::int64_t floor_id) { return sessions_.walkable_of(floor_id); };
    const auto levels_of = [this](std::int64_t floor_id) { return sessions_.levels_of(floor_id); };
    const auto it = held.find(id_);
    const bool continues = it != held.end() && (!latest || (it->second->done_t() && latest->t <= *it->second->done_t()));
    next_ = continues ? std::make_shared<ThinFusion>(*it->second)
                      : std::make_shared<ThinFusion>(method, static_cast<std::uint64_t>(id_), options);
    next_->set_anchors(std::move(anchors));
    if (!continues && latest) next_->resume(*latest, walkable_of);
    return next_->run(steps, radio, pressure, walkable_of, levels_of);
}

void FusionSessions::Run::keep() {
    if (next_) sessions_.fusions_[id_] = std::move(next_);
}

void FusionSessions::forget(const std::vector<std::int64_t>& ids) {
    if (ids.empty()) return;
    std::lock_guard lock(mu_);
    for (const auto id : ids) fusions_.erase(id);
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
