#include "tracks/track_cache.hpp"

#include <algorithm>

#include "tracks/track_rows.hpp"

namespace locus::tracks {

std::string forbidden_message(std::int64_t id) { return "the token does not open track " + std::to_string(id); }

void CachedTrack::remember(const Fix& f, std::size_t buffer) {
    recent.emplace_back(++seq, f);
    if (recent.size() > buffer) recent.pop_front();
}

void CachedTrack::go(double t) {
    info.state = State::gone;
    info.ended_at = t;
    info.latest.reset();
    info.fixes = 0;
    info.label.clear();
    shares.clear();
    recent.clear();
    changed.notify_all();
}

void TrackCache::load(store::TrackRepository& repo) {
    std::lock_guard lock(mu_);
    for (const auto& row : repo.tracks()) {
        auto t = std::make_shared<CachedTrack>();
        t->info = info_of(row);
        t->token_hash = row.token_hash;
        tracks_[t->info.id] = t;
    }
    for (const auto& row : repo.latest_fixes()) {
        if (auto it = tracks_.find(row.track_id); it != tracks_.end()) {
            it->second->info.latest = fix_of(row.fix);
            it->second->info.fixes = row.fixes;
        }
    }
    for (const auto& row : repo.shares())
        if (auto it = tracks_.find(row.track_id); it != tracks_.end()) it->second->shares[row.id] = row.token_hash;
}

std::shared_ptr<CachedTrack> TrackCache::find(std::int64_t id) const {
    const auto it = tracks_.find(id);
    if (it == tracks_.end()) throw Refused(Reason::forbidden, forbidden_message(id));
    return it->second;
}

std::shared_ptr<CachedTrack> TrackCache::lookup(std::int64_t id) const {
    const auto it = tracks_.find(id);
    return it == tracks_.end() ? nullptr : it->second;
}

std::size_t TrackCache::live() const {
    return static_cast<std::size_t>(std::count_if(tracks_.begin(), tracks_.end(), [](const auto& kv) { return kv.second->info.state == State::live; }));
}

void TrackCache::stop() {
    stopping_ = true;
    for (auto& [id, t] : tracks_) t->changed.notify_all();
}

std::vector<TrackInfo> TrackCache::live_on_map(std::int64_t map_id, std::optional<std::int64_t> floor_id) const {
    std::vector<TrackInfo> out;
    std::lock_guard lock(mu_);
    for (const auto& [id, t] : tracks_)
        if (t->info.map_id == map_id && t->info.state == State::live && t->info.latest &&
            (!floor_id || t->info.latest->floor_id == *floor_id))
            out.push_back(t->info);
    std::sort(out.begin(), out.end(), [](const TrackInfo& a, const TrackInfo& b) { return a.id < b.id; });
    return out;
}

bool TrackCache::is_stopping() const {
    std::lock_guard lock(mu_);
    return stopping_;
}

}  // namespace locus::tracks
