#include "tracks/replication.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <utility>

#include "tracks/service.hpp"
#include "tracks/track_rows.hpp"

namespace locus::tracks {

void Replication::start() {
    if (repo_.replicated()) refresher_ = std::thread([this] { run(); });
}

void Replication::join() {
    if (refresher_.joinable()) refresher_.join();
}

void Replication::refresh(std::int64_t id) {
    std::lock_guard db_lock(repo_.mutex());
    // Every read below from one snapshot (REPEATABLE READ on PostgreSQL): a fix committing
    // between two of them would otherwise leave the latest fix read stale while "the fixes
    // since" already held it, and the next refresh would append it a second time.
    store::TrackRepository::Snapshot snapshot(repo_);
    const auto stored = repo_.track(id);
    if (!stored) {
        vanished(id);
        return;
    }
    Read r = read(id, *stored);
    snapshot.commit();
    apply(id, std::move(r));
}

void Replication::vanished(std::int64_t id) {
    // Its map was deleted (the row went with it): gone, 404, as on the server that deleted
    // it. Else another server evicted it at --max-tracks: dropped, as the evicting server
    // dropped it, so its tokens answer 403 here too. Either way its streams end.
    std::optional<std::int64_t> map_id;
    {
        std::lock_guard lock(cache_.mutex());
        if (const auto t = cache_.lookup(id)) map_id = t->info.map_id;
    }
    if (!map_id) return;  // unknown here too: refused as forbidden
    const bool map_exists = repo_.map_exists(*map_id);
    std::lock_guard lock(cache_.mutex());
    if (const auto t = cache_.lookup(id)) {
        if (t->info.state != State::gone) streams_.mark_gone(*t, Service::now());
        if (map_exists) cache_.erase(id);
    }
}

Replication::Read Replication::read(std::int64_t id, const store::TrackRow& stored) {
    Read r;
    r.row = info_of(stored);
    r.hash = stored.token_hash;
    if (const auto latest = repo_.latest_fix(id)) r.row.latest = fix_of(*latest);
    // The latest fix held here; the repository's mutex keeps this server's own posts out until the end.
    std::optional<double> held_t;
    bool known = false;
    {
        std::lock_guard lock(cache_.mutex());
        if (const auto t = cache_.lookup(id)) {
            known = true;
            if (t->info.latest) held_t = t->info.latest->t;
        }
    }
    // The fixes stored since (by t, oldest first, as many as a stream buffers): what this
    // server's streams would have been given had they been posted here. A track new here has no
    // stream yet: its latest fix is enough.
    if (r.row.latest && (!held_t || r.row.latest->t > *held_t)) {
        if (!known) r.fresh.push_back(*r.row.latest);
        else
            for (const auto& f : repo_.last_fixes(id, held_t, options_.event_buffer)) r.fresh.push_back(fix_of(f));
    }
    // The count is kept by adding what is new (a count(*) would read every fix of the track on
    // each remote fix); counted only for a track new here, or when more came than were read.
    if (!known || r.fresh.size() >= options_.event_buffer) r.counted = repo_.fix_count(id);
    r.shares = repo_.shares_of(id);
    return r;
}

void Replication::apply(std::int64_t id, Read r) {
    const TrackInfo& row = r.row;
    std::lock_guard lock(cache_.mutex());
    auto& slot = cache_.slot(id);
    const bool known = slot != nullptr;  // a map deletion may have dropped it meanwhile (it holds no repository lock)
    if (!slot) slot = std::make_shared<CachedTrack>();
    CachedTrack& t = *slot;
    if (known && t.info.state == State::gone) return;  // a tombstone stays one
    if (row.state == State::gone) {
        // Deleted or expired on another server: its map is no longer stored in the row, so the
        // tombstone is made from what this server held, as a local delete makes it.
        t.token_hash = r.hash;
        if (known) streams_.mark_gone(t, row.ended_at.value_or(Service::now()));
        else t.info = row;
        return;
    }
    const bool was_live = known && t.info.state == State::live;
    const bool revoked = std::any_of(t.shares.begin(), t.shares.end(), [&](const auto& s) { return !r.shares.contains(s.first); });
    // Only fixes past the latest held now are new: a fix is never given to a stream twice.
    if (known && t.info.latest) {
        const double held = t.info.latest->t;
        std::erase_if(r.fresh, [held](const Fix& f) { return f.t <= held; });
    }
    const std::size_t fixes_before = known ? t.info.fixes : 0;
    const auto latest_before = known ? t.info.latest : std::nullopt;
    t.info = row;
    t.info.fixes = r.counted ? *r.counted : fixes_before + r.fresh.size();
    if (latest_before && (!t.info.latest || t.info.latest->t < latest_before->t)) t.info.latest = latest_before;
    t.token_hash = r.hash;
    t.shares = std::move(r.shares);
    for (const auto& f : r.fresh) t.remember(f, options_.event_buffer);
    const bool ended = was_live && row.state != State::live;
    if (!r.fresh.empty() || ended || revoked) t.changed.notify_all();
    // The map's positions streams: the new latest position, then the end, as local writes publish them.
    if (!r.fresh.empty() && (was_live || row.state == State::live)) streams_.publish(t.info, t.info.latest);
    if (ended) streams_.publish(t.info, std::nullopt);
}

void Replication::on_track_change(std::int64_t id, std::optional<std::int64_t> map_id) {
    std::lock_guard lock(cache_.mutex());
    if (cache_.stopping()) return;
    bool cares = map_id && streams_.map_watched(*map_id);
    if (const auto t = cache_.lookup(id); !cares && t) cares = t->streams > 0 || streams_.map_watched(t->info.map_id);
    // Any other track is read again when a request for it comes (authorize).
    if (!cares) return;
    queue_refresh(id);
}

void Replication::queue_refresh(std::int64_t id) {
    if (!repo_.replicated()) return;  // one server: nothing changes behind its back
    if (queued_.insert(id).second) to_refresh_.push_back(id);
    refresh_cv_.notify_one();
}

void Replication::catch_up_later() {
    if (!repo_.replicated()) return;
    catch_up_ = true;
    refresh_cv_.notify_one();
}

void Replication::catch_up_map_later(std::int64_t map_id) {
    if (!repo_.replicated()) return;
    maps_to_catch_up_.insert(map_id);
    refresh_cv_.notify_one();
}

void Replication::wake() { refresh_cv_.notify_all(); }

void Replication::catch_up_map(std::int64_t map_id) {
    std::unordered_set<std::int64_t> ids;
    {
        std::lock_guard db_lock(repo_.mutex());
        for (const auto id : repo_.live_on_map(map_id)) ids.insert(id);
    }
    {
        std::lock_guard lock(cache_.mutex());  // and those live here that may have ended elsewhere
        for (const auto& [id, t] : cache_.all())
            if (t->info.map_id == map_id && t->info.state == State::live) ids.insert(id);
    }
    for (const auto id : ids) {
        if (cache_.is_stopping()) return;  // a slow PostgreSQL must not hold shutdown back
        refresh(id);
    }
}

void Replication::catch_up() {
    std::vector<std::int64_t> ids, maps;
    {
        std::lock_guard lock(cache_.mutex());
        for (const auto& [id, t] : cache_.all())
            if (t->streams > 0) ids.push_back(id);
        maps = streams_.watched_maps();
    }
    for (const auto id : ids) {
        if (cache_.is_stopping()) return;
        refresh(id);
    }
    for (const auto map_id : maps) catch_up_map(map_id);
}

void Replication::run() {
    // After a storage fault the failed work is queued again and retried after a pause, 0.1 s
    // doubling to at most 5 s while faults go on: a fault on this connection alone (the
    // watcher's still up) brings no "everything changed" to make good what was dropped.
    double retry_s = 0;
    std::unique_lock lock(cache_.mutex());
    while (!cache_.stopping()) {
        if (retry_s > 0) refresh_cv_.wait_for(lock, std::chrono::duration<double>(retry_s), [this] { return cache_.stopping(); });
        else
            refresh_cv_.wait(lock, [this] { return cache_.stopping() || catch_up_ || !to_refresh_.empty() || !maps_to_catch_up_.empty(); });
        if (cache_.stopping()) break;
        const bool all = std::exchange(catch_up_, false);
        const auto ids = std::exchange(to_refresh_, {});
        queued_.clear();
        const auto maps = std::exchange(maps_to_catch_up_, {});
        lock.unlock();
        bool all_failed = false;
        std::vector<std::int64_t> failed_maps, failed_ids;
        if (all) try {
                catch_up();
            } catch (const std::exception&) {
                all_failed = true;
            }
        for (const auto map_id : maps) try {
                catch_up_map(map_id);
            } catch (const std::exception&) {
                failed_maps.push_back(map_id);
            }
        for (const auto id : ids) {
            if (cache_.is_stopping()) break;
            try {
                refresh(id);
            } catch (const std::exception&) {
                failed_ids.push_back(id);
            }
        }
        lock.lock();
        if (all_failed) catch_up_ = true;
        maps_to_catch_up_.insert(failed_maps.begin(), failed_maps.end());
        for (const auto id : failed_ids)
            if (queued_.insert(id).second) to_refresh_.push_back(id);
        const bool failed = all_failed || !failed_maps.empty() || !failed_ids.empty();
        retry_s = failed ? std::clamp(retry_s * 2, 0.1, 5.0) : 0;
    }
}

}  // namespace locus::tracks
