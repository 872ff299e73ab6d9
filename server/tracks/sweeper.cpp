#include "tracks/sweeper.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <unordered_map>
#include <utility>

#include "tracks/service.hpp"

namespace locus::tracks {

void Sweeper::start(std::function<void()> work) {
    thread_ = std::thread([this, work = std::move(work)] { run(work); });
}

void Sweeper::join() {
    if (thread_.joinable()) thread_.join();
}

void Sweeper::wake() { sweep_cv_.notify_all(); }

std::vector<std::shared_ptr<CachedTrack>> Sweeper::evictable(std::size_t n) const {
    Tracks out;
    for (const auto& [id, tr] : cache_.all())
        if (tr->info.state != State::live) out.push_back(tr);
    const auto first_to_go = [](const std::shared_ptr<CachedTrack>& a, const std::shared_ptr<CachedTrack>& b) {
        const bool a_closed = a->info.state == State::closed, b_closed = b->info.state == State::closed;
        if (a_closed != b_closed) return b_closed;  // tombstones first: they hold nothing but a 404
        return std::pair(a->info.ended_at.value_or(0), a->info.id) < std::pair(b->info.ended_at.value_or(0), b->info.id);
    };
    n = std::min(n, out.size());
    std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), first_to_go);
    out.resize(n);
    return out;
}

Sweeper::Tracks Sweeper::still_quiet(const Tracks& to_close, double t, std::vector<std::int64_t>& ended_elsewhere) {
    // Another server sharing the database may have stored fixes this one has not seen:
    // a track is closed only when the database says it has been quiet too.
    Tracks quiet;
    for (const auto& tr : to_close) {
        const auto at = repo_.live_last_fix_at(tr->info.id);
        if (!at) {
            // Closed, deleted or evicted on another server whose notification never came:
            // read again (the refresher), so it ends here too and its streams with it.
            ended_elsewhere.push_back(tr->info.id);
            continue;
        }
        if (*at + options_.ttl_s < t) {
            quiet.push_back(tr);
        } else {
            std::lock_guard lock(cache_.mutex());
            tr->info.last_fix_at = *at;
        }
    }
    return quiet;
}

std::vector<std::int64_t> Sweeper::sweep() {
    const double t = Service::now();
    std::lock_guard db_lock(repo_.mutex());
    Tracks to_close, to_purge, to_forget;
    {
        std::lock_guard lock(cache_.mutex());
        for (const auto& [id, tr] : cache_.all()) {
            if (tr->info.state == State::live && tr->info.last_fix_at + options_.ttl_s < t) to_close.push_back(tr);
            else if (tr->info.state == State::closed && tr->info.ended_at && *tr->info.ended_at + options_.retention_s < t) to_purge.push_back(tr);
            else if (tr->info.state == State::gone && tr->info.ended_at && *tr->info.ended_at + options_.retention_s < t) to_forget.push_back(tr);
        }
    }
    store::TrackRepository::Write tx(repo_);
    std::vector<std::int64_t> ended_elsewhere;
    if (repo_.is_postgres()) to_close = still_quiet(to_close, t, ended_elsewhere);
    for (const auto& tr : to_close) repo_.close(tr->info.id, t);
    for (const auto& tr : to_purge) repo_.purge(tr->info.id, t);
    for (const auto& tr : to_forget) repo_.forget(tr->info.id);
    // A long live track keeps only its last retention period of fixes.
    const bool trimmed = repo_.trim_fixes(t - options_.retention_s);
    std::unordered_map<std::int64_t, std::size_t> kept;  // fixes left per track, when some were trimmed
    if (trimmed) kept = repo_.fix_counts();
    std::vector<std::pair<std::int64_t, std::int64_t>> ended_here;
    for (const auto* list : {&to_close, &to_purge})
        for (const auto& tr : *list) ended_here.emplace_back(tr->info.id, tr->info.map_id);
    repo_.announce(ended_here);
    tx.commit();

    std::lock_guard lock(cache_.mutex());
    for (const auto id : ended_elsewhere) replication_.queue_refresh(id);
    for (const auto& tr : to_close) {
        tr->info.state = State::closed;
        tr->info.ended_at = t;
        tr->changed.notify_all();
        streams_.publish(tr->info, std::nullopt);
    }
    for (const auto& tr : to_purge) streams_.mark_gone(*tr, t);
    for (const auto& tr : to_forget) cache_.erase(tr->info.id);
    std::vector<std::int64_t> ended;
    for (const auto& [id, tr] : cache_.all())
        if (tr->info.state != State::live) ended.push_back(id);
    if (trimmed) {
        // Counts and latest fixes of tracks that lost old fixes: rare (a track older than the
        // retention period), so the counts are read again; without this a track posting for
        // longer than max_fixes_per_track allows would be refused as full.
        for (const auto& [id, tr] : cache_.all()) {
            if (tr->info.latest && tr->info.latest->t < t - options_.retention_s) tr->info.latest.reset();
            const auto left = kept.find(id);
            tr->info.fixes = left == kept.end() ? 0 : left->second;
        }
    }
    return ended;
}

void Sweeper::run(const std::function<void()>& work) {
    const double period = std::clamp(std::min(options_.ttl_s, options_.retention_s) / 4, 0.05, 5.0);
    std::unique_lock lock(cache_.mutex());
    while (!cache_.stopping()) {
        sweep_cv_.wait_for(lock, std::chrono::duration<double>(period));
        if (cache_.stopping()) break;
        lock.unlock();
        try {
            work();
        } catch (const std::exception&) {
            // A storage fault now is retried at the next sweep.
        }
        lock.lock();
    }
}

}  // namespace locus::tracks
