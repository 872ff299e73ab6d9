#include "tracks/service.hpp"

#include <algorithm>
#include <chrono>

#include "store/kinds.hpp"
#include "store/pg_changes.hpp"
#include "tracks/fusion.hpp"
#include "tracks/token.hpp"

namespace locus::tracks {

struct Service::Track {
    TrackInfo info;
    std::string token_hash;
    std::map<std::int64_t, std::string> shares;  // share id -> token hash
    std::uint64_t seq = 0;                       // fixes stored so far, for streams
    std::deque<std::pair<std::uint64_t, Fix>> recent;
    std::condition_variable changed;  // waited on with mu_
    std::size_t streams = 0;          // event streams open on it
};

const char* state_name(State s) {
    switch (s) {
        case State::live: return "live";
        case State::closed: return "closed";
        case State::gone: return "gone";
    }
    return "live";
}

namespace {

State state_of(const std::string& s) { return s == "live" ? State::live : s == "closed" ? State::closed : State::gone; }

Fix fix_of(store::Stmt& q, int c) {
    Fix f;
    f.t = q.real(c);
    f.floor_id = q.int64(c + 1);
    f.x = q.real(c + 2);
    f.y = q.real(c + 3);
    f.accuracy_m = q.real(c + 4);
    if (!q.is_null(c + 5)) f.heading_deg = q.real(c + 5);
    return f;
}

std::string forbidden_message(std::int64_t id) {
    return "the token does not open track " + std::to_string(id);
}

}  // namespace

double Service::now() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

Service::Service(store::Store& store, Options options)
    : store_(store), options_(options), db_(store.connection()), origin_(store.change_origin()) {
    if (options_.client_key.empty()) options_.client_key = token_hash(new_token("key_"));
    load();
    subscription_ = store_.subscribe([this](const store::Change& c) {
        if (c.kind == &store::track_kind()) {
            on_track_change(c.id, c.map_id);
            return;
        }
        if (c.plan || (c.kind && c.kind->name == "floors")) {
            std::lock_guard lock(fusion_mu_);
            walkables_.erase(c.id);
        }
        // A deleted map took its floors by cascade, without a change each; it is also how
        // another server's "everything changed" arrives (store/pg_changes.hpp): drop them all.
        if (!c.plan && c.deleted && c.kind && c.kind->name == "maps") {
            std::lock_guard lock(fusion_mu_);
            walkables_.clear();
        }
        // A floor, building or map deleted or moved: which floors are on which map is asked again.
        if (!c.plan && c.kind && (c.kind->name == "floors" || c.kind->name == "buildings" || c.kind->name == "maps")) {
            std::lock_guard lock(mu_);
            floors_of_map_.clear();
        }
        if (!c.plan && c.deleted && c.kind && c.kind->name == "maps") map_deleted(c.id);
        // "Everything changed" (a map id 0 cannot be deleted otherwise): notifications of other
        // servers' track writes may have been missed too.
        if (!c.plan && c.deleted && c.kind && c.kind->name == "maps" && c.id == 0 && !origin_.empty()) {
            std::lock_guard lock(mu_);
            catch_up_ = true;
            refresh_cv_.notify_one();
        }
    });
    sweeper_ = std::thread([this] { sweeper(); });
    if (!origin_.empty()) refresher_ = std::thread([this] { refresher(); });
}

Service::~Service() {
    store_.unsubscribe(subscription_);
    stop();
    if (sweeper_.joinable()) sweeper_.join();
    if (refresher_.joinable()) refresher_.join();
}

void Service::stop() {
    std::lock_guard lock(mu_);
    stopping_ = true;
    sweep_cv_.notify_all();
    refresh_cv_.notify_all();
    for (auto& [id, t] : tracks_) t->changed.notify_all();
    map_changed_.notify_all();
}

void Service::publish(const TrackInfo& track, std::optional<Fix> fix) {
    map_changes_.push_back({++map_seq_, track.map_id, track.id, track.label, fix});
    if (map_changes_.size() > options_.map_event_buffer) map_changes_.pop_front();
    map_changed_.notify_all();
}

void Service::mark_gone(Track& track, double t) {
    if (track.info.state == State::live) publish(track.info, std::nullopt);
    track.info.state = State::gone;
    track.info.ended_at = t;
    track.info.latest.reset();
    track.info.fixes = 0;
    track.info.label.clear();
    track.shares.clear();
    track.recent.clear();
    track.changed.notify_all();
}

void Service::map_deleted(std::int64_t map_id) {
    const double t = now();
    std::lock_guard lock(mu_);
    for (auto& [id, track] : tracks_)
        if (track->info.map_id == map_id && track->info.state != State::gone) mark_gone(*track, t);
}

void Service::load() {
    std::lock_guard db_lock(db_mu_);
    std::lock_guard lock(mu_);
    store::Stmt q(db_, "SELECT id, map_id, label, token_hash, state, created_at, last_fix_at, ended_at, fusion, fusion_options FROM tracks");
    while (q.step()) {
        auto t = std::make_shared<Track>();
        t->info.id = q.int64(0);
        t->info.map_id = q.is_null(1) ? 0 : q.int64(1);
        t->info.label = q.is_null(2) ? "" : q.text(2);
        t->token_hash = q.blob(3);
        t->info.state = state_of(q.text(4));
        t->info.created_at = q.real(5);
        t->info.last_fix_at = q.real(6);
        if (!q.is_null(7)) t->info.ended_at = q.real(7);
        t->info.fusion = fusion_method_of(q.text(8)).value_or(FusionMethod::walk_pf);
        if (!q.is_null(9)) t->info.fusion_options = fusion_options_of_text(q.text(9));
        tracks_[t->info.id] = t;
    }
    store::Stmt latest(db_,
                       "SELECT track_id, t, floor_id, x, y, accuracy_m, heading_deg, n FROM "
                       "(SELECT track_id, t, floor_id, x, y, accuracy_m, heading_deg, "
                       "row_number() OVER (PARTITION BY track_id ORDER BY t DESC) AS r, "
                       "count(*) OVER (PARTITION BY track_id) AS n FROM track_fixes) AS latest WHERE r = 1");
    while (latest.step()) {
        if (auto it = tracks_.find(latest.int64(0)); it != tracks_.end()) {
            it->second->info.latest = fix_of(latest, 1);
            it->second->info.fixes = static_cast<std::size_t>(latest.int64(7));
        }
    }
    store::Stmt shares(db_, "SELECT id, track_id, token_hash FROM track_shares");
    while (shares.step())
        if (auto it = tracks_.find(shares.int64(1)); it != tracks_.end()) it->second->shares[shares.int64(0)] = shares.blob(2);
}

std::shared_ptr<Service::Track> Service::find(std::int64_t id) const {
    const auto it = tracks_.find(id);
    if (it == tracks_.end()) throw Refused(Reason::forbidden, forbidden_message(id));
    return it->second;
}

std::vector<std::shared_ptr<Service::Track>> Service::evictable(std::size_t n) const {
    std::vector<std::shared_ptr<Track>> out;
    for (const auto& [id, tr] : tracks_)
        if (tr->info.state != State::live) out.push_back(tr);
    const auto first_to_go = [](const std::shared_ptr<Track>& a, const std::shared_ptr<Track>& b) {
        const bool a_closed = a->info.state == State::closed, b_closed = b->info.state == State::closed;
        if (a_closed != b_closed) return b_closed;  // tombstones first: they hold nothing but a 404
        return std::pair(a->info.ended_at.value_or(0), a->info.id) < std::pair(b->info.ended_at.value_or(0), b->info.id);
    };
    n = std::min(n, out.size());
    std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), first_to_go);
    out.resize(n);
    return out;
}

Opened Service::open(std::int64_t map_id, const std::string& label, FusionMethod fusion, const FusionOptions& options,
                     const std::optional<std::string>& client) {
    (void)store_.get(store::kind("maps"), map_id);  // NotFound for an unknown map
    Opened out;
    out.token = new_token("trk_");
    const std::string hash = token_hash(out.token);
    const double t = now();
    std::vector<std::shared_ptr<Track>> evicted;
    {
        std::lock_guard db_lock(db_mu_);
        {
            std::lock_guard lock(mu_);
            const auto live = std::count_if(tracks_.begin(), tracks_.end(), [](const auto& kv) { return kv.second->info.state == State::live; });
            if (static_cast<std::size_t>(live) >= options_.max_live_tracks)
                throw Refused(Reason::busy, "the server follows " + std::to_string(live) + " live tracks, its most; try again later");
            // Closed tracks and tombstones give way to a live one: an anonymous loop of opens
            // and deletes (or closes) must not refuse everyone else's opens for a retention period.
            if (tracks_.size() >= options_.max_tracks) {
                const std::size_t over = tracks_.size() + 1 - options_.max_tracks;
                evicted = evictable(over);
                if (evicted.size() < over)
                    throw Refused(Reason::too_many_tracks, "the server follows " + std::to_string(live) +
                                                               " live tracks, as many as it holds at all (--max-tracks); try again later");
            }
        }
        out.info = insert_track(map_id, label, fusion, options, hash, t, evicted, client ? keyed_hash(options_.client_key, *client) : "");
    }
    // With no other lock held: post_raw takes fusion_mu_ first. Only when something was
    // evicted: fusion_mu_ is held through a whole filter run, which an open need not wait for.
    if (!evicted.empty()) {
        std::lock_guard fusion_lock(fusion_mu_);
        for (const auto& tr : evicted) fusions_.erase(tr->info.id);
    }
    return out;
}

TrackInfo Service::insert_track(std::int64_t map_id, const std::string& label, FusionMethod fusion, const FusionOptions& options,
                                const std::string& hash, double t, const std::vector<std::shared_ptr<Track>>& evicted,
                                const std::string& client_hash) {
    store::Transaction tx(db_);
    if (!client_hash.empty()) {
        // Replicas count in one order: two opens of one client on two servers cannot both
        // see room for one more. Any constant: the lock only serializes these counts.
        if (db_.is_postgres()) db_.exec("SELECT pg_advisory_xact_lock(7343469)");
        // A live track past --track-ttl that no sweeper closed yet (its server died) holds nothing.
        store::Stmt q(db_, "SELECT count(*), min(last_fix_at) FROM tracks WHERE client_hash = ? AND state = 'live' AND last_fix_at >= ?");
        q.bind_blob(1, client_hash).bind(2, t - options_.ttl_s);
        q.step();
        const auto held = static_cast<std::size_t>(q.int64(0));
        // The client's next track frees when its quietest one reaches --track-ttl without a fix.
        if (held >= options_.max_live_tracks_per_client)
            throw Refused(Reason::client_live_tracks,
                          "this client holds " + std::to_string(held) + " live tracks, its most (--client-live-tracks " +
                              std::to_string(options_.max_live_tracks_per_client) + "); close one first",
                          std::max(1.0, q.real(1) + options_.ttl_s - t));
    }
    for (const auto& tr : evicted) {
        store::Stmt(db_, "DELETE FROM track_fixes WHERE track_id = ?").bind(1, tr->info.id).run();
        store::Stmt(db_, "DELETE FROM track_shares WHERE track_id = ?").bind(1, tr->info.id).run();
        store::Stmt(db_, "DELETE FROM tracks WHERE id = ?").bind(1, tr->info.id).run();
    }
    store::Stmt ins(db_, "INSERT INTO tracks (map_id, label, token_hash, state, created_at, last_fix_at, fusion, fusion_options, client_hash) "
                         "VALUES (?, ?, ?, 'live', ?, ?, ?, ?, ?)");
    ins.bind(1, map_id);
    if (label.empty()) ins.bind_null(2);
    else ins.bind(2, std::string_view(label));
    ins.bind_blob(3, hash).bind(4, t).bind(5, t).bind(6, std::string_view(fusion_method_stored_name(fusion)));
    const std::string options_text = fusion_options_text(options);
    if (options_text.empty()) ins.bind_null(7);
    else ins.bind(7, std::string_view(options_text));
    if (client_hash.empty()) ins.bind_null(8);
    else ins.bind_blob(8, client_hash);
    ins.run();
    const std::int64_t id = db_.last_insert_id();
    tx.commit();
    auto track = std::make_shared<Track>();
    track->info = {id, map_id, label, State::live, t, t, std::nullopt, std::nullopt, 0, fusion, options};
    track->token_hash = hash;
    std::lock_guard lock(mu_);
    for (const auto& tr : evicted) {
        if (tr->info.state != State::gone) mark_gone(*tr, t);  // its streams end
        tracks_.erase(tr->info.id);
    }
    tracks_[id] = track;
    return track->info;
}

void Service::refresh(std::int64_t id) {
    std::lock_guard db_lock(db_mu_);
    // Every read below from one snapshot (REPEATABLE READ on PostgreSQL): a fix committing
    // between two of them would otherwise leave the latest fix read stale while "the fixes
    // since" already held it, and the next refresh would append it a second time.
    store::Transaction snapshot(db_, store::Transaction::Mode::read);
    store::Stmt q(db_, "SELECT map_id, label, token_hash, state, created_at, last_fix_at, ended_at, fusion, fusion_options FROM tracks WHERE id = ?");
    q.bind(1, id);
    if (!q.step()) {
        // Its map was deleted (the row went with it): gone, 404, as on the server that deleted
        // it. Else another server evicted it at --max-tracks: dropped, as the evicting server
        // dropped it, so its tokens answer 403 here too. Either way its streams end.
        std::optional<std::int64_t> map_id;
        {
            std::lock_guard lock(mu_);
            if (const auto it = tracks_.find(id); it != tracks_.end()) map_id = it->second->info.map_id;
        }
        if (!map_id) return;  // unknown here too: refused as forbidden
        store::Stmt m(db_, "SELECT 1 FROM maps WHERE id = ?");
        m.bind(1, *map_id);
        const bool map_exists = m.step();
        std::lock_guard lock(mu_);
        if (const auto it = tracks_.find(id); it != tracks_.end()) {
            if (it->second->info.state != State::gone) mark_gone(*it->second, now());
            if (map_exists) tracks_.erase(it);
        }
        return;
    }
    TrackInfo row;
    row.id = id;
    row.map_id = q.is_null(0) ? 0 : q.int64(0);
    row.label = q.is_null(1) ? "" : q.text(1);
    const std::string hash = q.blob(2);
    row.state = state_of(q.text(3));
    row.created_at = q.real(4);
    row.last_fix_at = q.real(5);
    if (!q.is_null(6)) row.ended_at = q.real(6);
    row.fusion = fusion_method_of(q.text(7)).value_or(FusionMethod::walk_pf);
    if (!q.is_null(8)) row.fusion_options = fusion_options_of_text(q.text(8));
    store::Stmt latest(db_, "SELECT t, floor_id, x, y, accuracy_m, heading_deg FROM track_fixes WHERE track_id = ? ORDER BY t DESC LIMIT 1");
    latest.bind(1, id);
    if (latest.step()) row.latest = fix_of(latest, 0);
    // The latest fix held here; db_mu_ keeps this server's own posts out until the end.
    std::optional<double> held_t;
    bool known = false;
    {
        std::lock_guard lock(mu_);
        if (const auto it = tracks_.find(id); it != tracks_.end()) {
            known = true;
            if (it->second->info.latest) held_t = it->second->info.latest->t;
        }
    }
    // The fixes stored since (by t, oldest first, as many as a stream buffers): what this
    // server's streams would have been given had they been posted here. A track new here has no
    // stream yet: its latest fix is enough.
    std::vector<Fix> fresh;
    if (row.latest && (!held_t || row.latest->t > *held_t)) {
        if (!known) {
            fresh.push_back(*row.latest);
        } else {
            store::Stmt q_new(db_, held_t ? "SELECT t, floor_id, x, y, accuracy_m, heading_deg FROM track_fixes WHERE track_id = ? AND t > ? ORDER BY t DESC LIMIT ?"
                                          : "SELECT t, floor_id, x, y, accuracy_m, heading_deg FROM track_fixes WHERE track_id = ? ORDER BY t DESC LIMIT ?");
            q_new.bind(1, id);
            if (held_t) q_new.bind(2, *held_t).bind(3, options_.event_buffer);
            else q_new.bind(2, options_.event_buffer);
            while (q_new.step()) fresh.push_back(fix_of(q_new, 0));
            std::reverse(fresh.begin(), fresh.end());
        }
    }
    // The count is kept by adding what is new (a count(*) would read every fix of the track on
    // each remote fix); counted only for a track new here, or when more came than were read.
    std::optional<std::size_t> counted;
    if (!known || fresh.size() >= options_.event_buffer) {
        store::Stmt count(db_, "SELECT count(*) FROM track_fixes WHERE track_id = ?");
        count.bind(1, id);
        count.step();
        counted = static_cast<std::size_t>(count.int64(0));
    }
    std::map<std::int64_t, std::string> shares;
    store::Stmt sh(db_, "SELECT id, token_hash FROM track_shares WHERE track_id = ?");
    sh.bind(1, id);
    while (sh.step()) shares[sh.int64(0)] = sh.blob(1);
    snapshot.commit();

    std::lock_guard lock(mu_);
    auto& slot = tracks_[id];
    known = slot != nullptr;  // a map deletion may have dropped it meanwhile (map_deleted holds no db_mu_)
    if (!slot) slot = std::make_shared<Track>();
    Track& t = *slot;
    if (known && t.info.state == State::gone) return;  // a tombstone stays one
    if (row.state == State::gone) {
        // Deleted or expired on another server: its map is no longer stored in the row, so the
        // tombstone is made from what this server held, as a local delete makes it.
        t.token_hash = hash;
        if (known) mark_gone(t, row.ended_at.value_or(now()));
        else t.info = row;
        return;
    }
    const bool was_live = known && t.info.state == State::live;
    const bool revoked = std::any_of(t.shares.begin(), t.shares.end(), [&](const auto& s) { return !shares.contains(s.first); });
    // Only fixes past the latest held now are new: a fix is never given to a stream twice.
    if (known && t.info.latest) {
        const double held = t.info.latest->t;
        std::erase_if(fresh, [held](const Fix& f) { return f.t <= held; });
    }
    const std::size_t fixes_before = known ? t.info.fixes : 0;
    const auto latest_before = known ? t.info.latest : std::nullopt;
    t.info = row;
    t.info.fixes = counted ? *counted : fixes_before + fresh.size();
    if (latest_before && (!t.info.latest || t.info.latest->t < latest_before->t)) t.info.latest = latest_before;
    t.token_hash = hash;
    t.shares = std::move(shares);
    for (const auto& f : fresh) {
        t.recent.emplace_back(++t.seq, f);
        if (t.recent.size() > options_.event_buffer) t.recent.pop_front();
    }
    const bool ended = was_live && row.state != State::live;
    if (!fresh.empty() || ended || revoked) t.changed.notify_all();
    // The map's positions streams: the new latest position, then the end, as local writes publish them.
    if (!fresh.empty() && (was_live || row.state == State::live)) publish(t.info, t.info.latest);
    if (ended) publish(t.info, std::nullopt);
}

void Service::announce(const std::vector<std::pair<std::int64_t, std::int64_t>>& tracks) {
    if (origin_.empty() || tracks.empty()) return;
    std::vector<store::Change> changes;
    for (const auto& [id, map_id] : tracks)
        changes.push_back(store::Change{&store::track_kind(), id, false, false, std::nullopt, map_id});
    // A notification of many changes would pass PostgreSQL's payload limit and be sent as
    // "everything changed", dropping every server's caches: a sweep closing many tracks sends several.
    constexpr std::size_t kPerNotification = 50;
    for (std::size_t i = 0; i < changes.size(); i += kPerNotification) {
        const auto end = changes.begin() + static_cast<std::ptrdiff_t>(std::min(changes.size(), i + kPerNotification));
        store::announce_tracks(db_, origin_, std::vector<store::Change>(changes.begin() + static_cast<std::ptrdiff_t>(i), end));
    }
}

void Service::on_track_change(std::int64_t id, std::optional<std::int64_t> map_id) {
    std::lock_guard lock(mu_);
    if (stopping_) return;
    const auto watched = [&](std::int64_t m) {
        const auto it = map_streams_.find(m);
        return it != map_streams_.end() && it->second > 0;
    };
    bool cares = map_id && watched(*map_id);
    if (const auto it = tracks_.find(id); !cares && it != tracks_.end())
        cares = it->second->streams > 0 || watched(it->second->info.map_id);
    // Any other track is read again when a request for it comes (authorize).
    if (!cares) return;
    queue_refresh(id);
}

void Service::queue_refresh(std::int64_t id) {
    if (origin_.empty()) return;  // one server: nothing changes behind its back
    if (queued_.insert(id).second) to_refresh_.push_back(id);
    refresh_cv_.notify_one();
}

void Service::catch_up_map(std::int64_t map_id) {
    std::unordered_set<std::int64_t> ids;
    {
        std::lock_guard db_lock(db_mu_);
        store::Stmt q(db_, "SELECT id FROM tracks WHERE map_id = ? AND state = 'live'");
        q.bind(1, map_id);
        while (q.step()) ids.insert(q.int64(0));
    }
    {
        std::lock_guard lock(mu_);  // and those live here that may have ended elsewhere
        for (const auto& [id, t] : tracks_)
            if (t->info.map_id == map_id && t->info.state == State::live) ids.insert(id);
    }
    for (const auto id : ids) {
        if (stopping()) return;  // a slow PostgreSQL must not hold shutdown back
        refresh(id);
    }
}

void Service::catch_up() {
    std::vector<std::int64_t> ids, maps;
    {
        std::lock_guard lock(mu_);
        for (const auto& [id, t] : tracks_)
            if (t->streams > 0) ids.push_back(id);
        for (const auto& [map_id, n] : map_streams_)
            if (n > 0) maps.push_back(map_id);
    }
    for (const auto id : ids) {
        if (stopping()) return;
        refresh(id);
    }
    for (const auto map_id : maps) catch_up_map(map_id);
}

bool Service::stopping() const {
    std::lock_guard lock(mu_);
    return stopping_;
}

void Service::refresher() {
    // After a storage fault the failed work is queued again and retried after a pause, 0.1 s
    // doubling to at most 5 s while faults go on: a fault on this connection alone (the
    // watcher's still up) brings no "everything changed" to make good what was dropped.
    double retry_s = 0;
    std::unique_lock lock(mu_);
    while (!stopping_) {
        if (retry_s > 0) refresh_cv_.wait_for(lock, std::chrono::duration<double>(retry_s), [this] { return stopping_; });
        else refresh_cv_.wait(lock, [this] { return stopping_ || catch_up_ || !to_refresh_.empty() || !maps_to_catch_up_.empty(); });
        if (stopping_) break;
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
            if (stopping()) break;
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

Access Service::authorize(std::int64_t id, const std::string& token) {
    if (db_.is_postgres()) refresh(id);
    const std::string hash = token_hash(token);
    std::lock_guard lock(mu_);
    const auto t = find(id);
    if (same_hash(hash, t->token_hash)) {
        if (t->info.state == State::gone) throw Refused(Reason::gone, "track " + std::to_string(id) + " has expired or was deleted; its fixes are gone");
        return Access::owner;
    }
    if (t->info.state != State::gone)
        for (const auto& [share_id, share_hash] : t->shares)
            if (same_hash(hash, share_hash)) return Access::share;
    throw Refused(Reason::forbidden, forbidden_message(id));
}

std::optional<std::int64_t> Service::misplaced_floor(std::int64_t id, const std::vector<Fix>& fixes) {
    std::int64_t map_id = 0;
    std::unordered_set<std::int64_t> unknown;
    {
        std::lock_guard lock(mu_);
        map_id = find(id)->info.map_id;
        const auto& known = floors_of_map_[map_id];
        for (const auto& f : fixes)
            if (!known.contains(f.floor_id)) unknown.insert(f.floor_id);
    }
    for (const auto floor_id : unknown) {
        bool on_map = false;
        try {
            const auto floor = store_.get(store::kind("floors"), floor_id);
            on_map = store_.get(store::kind("buildings"), *floor.parent_id).parent_id == map_id;
        } catch (const store::NotFound&) {
        }
        if (!on_map) return floor_id;
        std::lock_guard lock(mu_);
        floors_of_map_[map_id].insert(floor_id);
    }
    return std::nullopt;
}

Posted Service::post(std::int64_t id, const std::vector<Fix>& fixes) {
    const double t_now = now();
    std::lock_guard db_lock(db_mu_);  // held to the end: two posts of one track publish in commit order
    std::shared_ptr<Track> track;
    std::int64_t map_id = 0;
    {
        std::lock_guard lock(mu_);
        track = find(id);
        map_id = track->info.map_id;
        if (track->info.state != State::live)
            throw Refused(Reason::closed, "track " + std::to_string(id) + " is " + state_name(track->info.state) + "; open a new one");
        if (track->info.fixes + fixes.size() > options_.max_fixes_per_track)
            throw Refused(Reason::full, "track " + std::to_string(id) + " holds " + std::to_string(track->info.fixes) +
                                            " fixes; at most " + std::to_string(options_.max_fixes_per_track) + " are kept: open a new track");
    }
    Posted out;
    std::vector<Fix> stored;
    store::Transaction tx(db_);
    store::Stmt ins(db_, "INSERT OR IGNORE INTO track_fixes (track_id, t, floor_id, x, y, accuracy_m, heading_deg) VALUES (?, ?, ?, ?, ?, ?, ?)");
    for (const auto& f : fixes) {
        ins.bind(1, id).bind(2, f.t).bind(3, f.floor_id).bind(4, f.x).bind(5, f.y).bind(6, f.accuracy_m);
        if (f.heading_deg) ins.bind(7, *f.heading_deg);
        else ins.bind_null(7);
        ins.run();
        if (db_.changes() == 1) stored.push_back(f);
        ins.reset();
    }
    store::Stmt up(db_, "UPDATE tracks SET last_fix_at = ? WHERE id = ?");
    up.bind(1, t_now).bind(2, id).run();
    if (!stored.empty()) announce({{id, map_id}});
    tx.commit();

    std::lock_guard lock(mu_);
    track->info.last_fix_at = t_now;
    track->info.fixes += stored.size();
    const auto before = track->info.latest;
    for (const auto& f : stored) {
        if (!track->info.latest || f.t > track->info.latest->t) track->info.latest = f;
        track->recent.emplace_back(++track->seq, f);
        if (track->recent.size() > options_.event_buffer) track->recent.pop_front();
    }
    if (!stored.empty()) track->changed.notify_all();
    if (track->info.latest && (!before || before->t != track->info.latest->t)) publish(track->info, track->info.latest);
    out.stored = stored.size();
    out.duplicates = fixes.size() - stored.size();
    out.latest = track->info.latest;
    return out;
}

std::pair<Posted, std::vector<Fix>> Service::post_raw(std::int64_t id, const std::vector<Step>& steps, const std::vector<RadioFix>& radio,
                                                     std::shared_ptr<const FloorAnchors> anchors) {
    std::lock_guard fusion_lock(fusion_mu_);
    FusionMethod method;
    FusionOptions options;
    std::optional<Fix> latest;
    {
        std::lock_guard lock(mu_);
        const auto& track = find(id);
        if (track->info.state != State::live)
            throw Refused(Reason::closed, "track " + std::to_string(id) + " is not live; open a new one");
        method = track->info.fusion;
        options = track->info.fusion_options;
        latest = track->info.latest;
    }
    const auto walkable_of = [this](std::int64_t floor_id) -> std::shared_ptr<const fusion::Walkable> {
        if (const auto w = walkables_.find(floor_id); w != walkables_.end()) return w->second;
        const auto stored = store_.plan_of_floor(floor_id);
        if (!stored) return nullptr;
        auto w = std::make_shared<const fusion::Walkable>(fusion::Walkable::from_plan(stored->plan));
        walkables_[floor_id] = w;
        return w;
    };
    // The filter runs on a copy, kept only once its fixes are stored. Its seed is the track's
    // id, so a track's fused fixes are reproducible (and client-lib's on the same inputs). A
    // filter this server does not hold (after a restart), or one the track's stored fixes have
    // passed (fixes posted directly, or steps another server sharing the database fused),
    // starts again at the track's latest stored fix rather than refusing the steps or
    // fusing from a stale state.
    const auto it = fusions_.find(id);
    const bool held = it != fusions_.end() && (!latest || (it->second->done_t() && latest->t <= *it->second->done_t()));
    auto next = held ? std::make_shared<ThinFusion>(*it->second) : std::make_shared<ThinFusion>(method, static_cast<std::uint64_t>(id), options);
    next->set_anchors(std::move(anchors));
    if (!held && latest) next->resume(*latest, walkable_of);
    std::vector<Fix> fused = next->run(steps, radio, walkable_of);
    // A radio fix and a step at one t give two fixes: the track keeps the later state. A t
    // stored by an earlier request (a retry) keeps the first fix, as posted fixes do.
    std::vector<Fix> kept;
    for (const Fix& f : fused) {
        if (!kept.empty() && kept.back().t == f.t) kept.back() = f;
        else kept.push_back(f);
    }
    Posted posted = post(id, kept);
    fusions_[id] = std::move(next);
    return {posted, std::move(fused)};
}

TrackInfo Service::close(std::int64_t id) {
    const double t = now();
    std::lock_guard db_lock(db_mu_);
    std::shared_ptr<Track> track;
    std::int64_t map_id = 0;
    {
        std::lock_guard lock(mu_);
        track = find(id);
        map_id = track->info.map_id;
        if (track->info.state != State::live) return track->info;  // closing twice is closing once
    }
    store::Transaction tx(db_);
    store::Stmt up(db_, "UPDATE tracks SET state = 'closed', ended_at = ?, client_hash = NULL WHERE id = ?");
    up.bind(1, t).bind(2, id).run();
    announce({{id, map_id}});
    tx.commit();
    std::lock_guard lock(mu_);
    track->info.state = State::closed;
    track->info.ended_at = t;
    track->changed.notify_all();
    publish(track->info, std::nullopt);
    return track->info;
}

void Service::remove(std::int64_t id) {
    const double t = now();
    std::lock_guard db_lock(db_mu_);
    std::shared_ptr<Track> track;
    std::int64_t map_id = 0;
    {
        std::lock_guard lock(mu_);
        track = find(id);
        map_id = track->info.map_id;
    }
    store::Transaction tx(db_);
    store::Stmt(db_, "DELETE FROM track_fixes WHERE track_id = ?").bind(1, id).run();
    store::Stmt(db_, "DELETE FROM track_shares WHERE track_id = ?").bind(1, id).run();
    store::Stmt(db_, "UPDATE tracks SET state = 'gone', map_id = NULL, label = NULL, ended_at = ?, client_hash = NULL WHERE id = ?")
        .bind(1, t)
        .bind(2, id)
        .run();
    announce({{id, map_id}});
    tx.commit();
    std::lock_guard lock(mu_);
    mark_gone(*track, t);
}

TrackInfo Service::info(std::int64_t id) const {
    std::lock_guard lock(mu_);
    return find(id)->info;
}

std::vector<Fix> Service::trail(std::int64_t id, std::size_t limit) {
    std::lock_guard db_lock(db_mu_);
    store::Stmt q(db_, "SELECT t, floor_id, x, y, accuracy_m, heading_deg FROM track_fixes WHERE track_id = ? ORDER BY t DESC LIMIT ?");
    q.bind(1, id).bind(2, limit);
    std::vector<Fix> out;
    while (q.step()) out.push_back(fix_of(q, 0));
    std::reverse(out.begin(), out.end());
    return out;
}

std::vector<TrackInfo> Service::live_on_map(std::int64_t map_id, std::optional<std::int64_t> floor_id) const {
    std::vector<TrackInfo> out;
    std::lock_guard lock(mu_);
    for (const auto& [id, t] : tracks_)
        if (t->info.map_id == map_id && t->info.state == State::live && t->info.latest &&
            (!floor_id || t->info.latest->floor_id == *floor_id))
            out.push_back(t->info);
    std::sort(out.begin(), out.end(), [](const TrackInfo& a, const TrackInfo& b) { return a.id < b.id; });
    return out;
}

Share Service::add_share(std::int64_t id) {
    Share out;
    out.track_id = id;
    out.token = new_token("shr_");
    const std::string hash = token_hash(out.token);
    std::lock_guard db_lock(db_mu_);
    std::shared_ptr<Track> track;
    {
        std::lock_guard lock(mu_);
        track = find(id);
        if (track->info.state != State::live)
            throw Refused(Reason::closed, "track " + std::to_string(id) + " is " + state_name(track->info.state) + ": there is nothing to share");
        if (track->shares.size() >= 100) throw Refused(Reason::full, "track " + std::to_string(id) + " has 100 shares, its most; revoke one first");
    }
    store::Stmt ins(db_, "INSERT INTO track_shares (track_id, token_hash, created_at) VALUES (?, ?, ?)");
    ins.bind(1, id).bind_blob(2, hash).bind(3, now()).run();
    out.id = db_.last_insert_id();
    std::lock_guard lock(mu_);
    track->shares[out.id] = hash;
    return out;
}

void Service::revoke_share(std::int64_t id, std::int64_t share_id) {
    std::lock_guard db_lock(db_mu_);
    std::shared_ptr<Track> track;
    std::int64_t map_id = 0;
    {
        std::lock_guard lock(mu_);
        track = find(id);
        map_id = track->info.map_id;
        if (!track->shares.contains(share_id))
            throw store::NotFound("track " + std::to_string(id) + " has no share " + std::to_string(share_id));
    }
    store::Transaction tx(db_);
    store::Stmt(db_, "DELETE FROM track_shares WHERE id = ?").bind(1, share_id).run();
    announce({{id, map_id}});
    tx.commit();
    std::lock_guard lock(mu_);
    track->shares.erase(share_id);
    track->changed.notify_all();  // its open streams end now
}

void Service::count_client_stream(const std::optional<std::string>& client) {
    if (!client) return;
    const auto it = client_streams_.find(*client);
    const std::size_t held = it == client_streams_.end() ? 0 : it->second;
    if (held >= options_.max_streams_per_client)
        throw Refused(Reason::client_streams, "this client has " + std::to_string(held) + " event streams open, its most (--client-streams " +
                                                  std::to_string(options_.max_streams_per_client) + "); close one first");
    ++client_streams_[*client];
}

void Service::uncount_client_stream(const std::optional<std::string>& client) {
    if (!client) return;
    const auto it = client_streams_.find(*client);
    if (it != client_streams_.end() && --it->second == 0) client_streams_.erase(it);
}

Service::Stream::~Stream() {
    std::lock_guard lock(service_.mu_);
    --service_.streams_;
    --track_->streams;
    service_.uncount_client_stream(client_);
}

std::unique_ptr<Service::Stream> Service::open_stream(std::int64_t id, const std::string& token, const std::optional<std::string>& client) {
    const bool shared = authorize(id, token) == Access::share;
    std::lock_guard lock(mu_);
    auto track = find(id);
    if (streams_ >= options_.max_streams)
        throw Refused(Reason::busy, "the server has " + std::to_string(streams_) + " event streams open, its most; try again later");
    if (track->streams >= options_.max_streams_per_track)
        throw Refused(Reason::too_many_streams, "track " + std::to_string(id) + " has " + std::to_string(track->streams) +
                                                    " event streams open, its most; close one first");
    count_client_stream(client);
    ++streams_;
    ++track->streams;
    std::unique_ptr<Stream> s(new Stream(*this, track));
    s->client_ = client;
    if (shared) s->share_hash_ = token_hash(token);
    s->seen_ = track->seq;
    // authorize() read the database before this stream was counted: another server's change
    // notified in between found no stream caring and was dropped. Read again now it counts.
    queue_refresh(id);
    return s;
}

Events Service::next_events(Stream& s) {
    std::unique_lock lock(mu_);
    Track& t = *s.track_;
    Events out;
    const auto revoked = [&] {
        if (!s.share_hash_) return false;
        for (const auto& [share_id, share_hash] : t.shares)
            if (same_hash(*s.share_hash_, share_hash)) return false;
        return true;
    };
    if (!s.started_) {
        s.started_ = true;
        // The latest fix stands for any stored since the stream opened: none is given twice.
        if (t.info.latest) out.fixes.push_back(*t.info.latest);
        s.seen_ = t.seq;
    } else {
        t.changed.wait_for(lock, std::chrono::duration<double>(options_.heartbeat_s),
                           [&] { return t.seq > s.seen_ || t.info.state != State::live || stopping_ || revoked(); });
        for (const auto& [seq, fix] : t.recent)
            if (seq > s.seen_) out.fixes.push_back(fix);
        s.seen_ = t.seq;
    }
    if (revoked()) out.fixes.clear();  // a revoked reader is told nothing more
    out.ended = t.info.state != State::live || stopping_ || revoked();
    return out;
}

Service::MapStream::~MapStream() {
    std::lock_guard lock(service_.mu_);
    --service_.streams_;
    if (const auto it = service_.map_streams_.find(map_id_); it != service_.map_streams_.end() && --it->second == 0)
        service_.map_streams_.erase(it);
    service_.uncount_client_stream(client_);
}

std::unique_ptr<Service::MapStream> Service::open_map_stream(std::int64_t map_id, std::optional<std::int64_t> floor_id,
                                                             const std::optional<std::string>& client) {
    std::unique_ptr<MapStream> s;
    {
        std::lock_guard lock(mu_);
        if (streams_ >= options_.max_streams)
            throw Refused(Reason::busy, "the server has " + std::to_string(streams_) + " event streams open, its most; try again later");
        count_client_stream(client);
        ++streams_;
        ++map_streams_[map_id];
        s.reset(new MapStream(*this, map_id, floor_id));
        s->client_ = client;
        // Other servers' tracks on the map, as the database holds them now, read on
        // refresher_'s thread: a request thread neither waits for their round trips nor fails
        // when PostgreSQL is away (retried there). Each arrives as a position; their later
        // changes come on the feed (on_track_change).
        if (!origin_.empty()) {
            maps_to_catch_up_.insert(map_id);
            refresh_cv_.notify_one();
        }
    }
    return s;
}

MapEvents Service::next_map_events(MapStream& s) {
    MapEvents out;
    if (!s.started_) {
        // The sequence is read before the snapshot: a change between the two is written twice
        // (positions are idempotent), never lost.
        {
            std::lock_guard lock(mu_);
            s.seen_ = map_seq_;
        }
        const auto now_live = live_on_map(s.map_id_, s.floor_id_);
        s.started_ = true;
        for (const auto& t : now_live) {
            out.events.push_back({MapEvent::Kind::position, t.id, t.label, t.latest});
            s.shown_.insert(t.id);
        }
        std::lock_guard lock(mu_);
        out.ended = stopping_;
        return out;
    }
    std::unique_lock lock(mu_);
    map_changed_.wait_for(lock, std::chrono::duration<double>(options_.heartbeat_s), [&] { return map_seq_ > s.seen_ || stopping_; });
    // A stream that fell more than map_event_buffer changes behind misses the oldest: the next
    // fix of each track shows it again.
    for (const auto& c : map_changes_) {
        if (c.seq <= s.seen_ || c.map_id != s.map_id_) continue;
        if (c.fix && (!s.floor_id_ || c.fix->floor_id == *s.floor_id_)) {
            out.events.push_back({MapEvent::Kind::position, c.track_id, c.label, c.fix});
            s.shown_.insert(c.track_id);
        } else if (s.shown_.erase(c.track_id)) {
            out.events.push_back({MapEvent::Kind::leave, c.track_id, c.label, c.fix});
        }
    }
    s.seen_ = map_seq_;
    out.ended = stopping_;
    return out;
}

void Service::sweep() {
    const auto ended = sweep_tracks();
    std::lock_guard fusion_lock(fusion_mu_);  // with no other lock held: post_raw takes it first
    for (const auto id : ended) fusions_.erase(id);
}

std::vector<std::int64_t> Service::sweep_tracks() {
    const double t = now();
    std::lock_guard db_lock(db_mu_);
    std::vector<std::shared_ptr<Track>> to_close, to_purge, to_forget;
    {
        std::lock_guard lock(mu_);
        for (const auto& [id, tr] : tracks_) {
            if (tr->info.state == State::live && tr->info.last_fix_at + options_.ttl_s < t) to_close.push_back(tr);
            else if (tr->info.state == State::closed && tr->info.ended_at && *tr->info.ended_at + options_.retention_s < t) to_purge.push_back(tr);
            else if (tr->info.state == State::gone && tr->info.ended_at && *tr->info.ended_at + options_.retention_s < t) to_forget.push_back(tr);
        }
    }
    store::Transaction tx(db_);
    std::vector<std::int64_t> ended_elsewhere;
    if (db_.is_postgres()) {
        // Another server sharing the database may have stored fixes this one has not seen:
        // a track is closed only when the database says it has been quiet too.
        std::vector<std::shared_ptr<Track>> quiet;
        for (const auto& tr : to_close) {
            store::Stmt last(db_, "SELECT last_fix_at FROM tracks WHERE id = ? AND state = 'live'");
            last.bind(1, tr->info.id);
            if (!last.step()) {
                // Closed, deleted or evicted on another server whose notification never came:
                // read again (refresher_), so it ends here too and its streams with it.
                ended_elsewhere.push_back(tr->info.id);
                continue;
            }
            const double at = last.real(0);
            if (at + options_.ttl_s < t) {
                quiet.push_back(tr);
            } else {
                std::lock_guard lock(mu_);
                tr->info.last_fix_at = at;
            }
        }
        to_close = std::move(quiet);
    }
    for (const auto& tr : to_close)
        store::Stmt(db_, "UPDATE tracks SET state = 'closed', ended_at = ?, client_hash = NULL WHERE id = ?").bind(1, t).bind(2, tr->info.id).run();
    for (const auto& tr : to_purge) {
        store::Stmt(db_, "DELETE FROM track_fixes WHERE track_id = ?").bind(1, tr->info.id).run();
        store::Stmt(db_, "DELETE FROM track_shares WHERE track_id = ?").bind(1, tr->info.id).run();
        store::Stmt(db_, "UPDATE tracks SET state = 'gone', map_id = NULL, label = NULL, ended_at = ? WHERE id = ?")
            .bind(1, t).bind(2, tr->info.id).run();
    }
    for (const auto& tr : to_forget) store::Stmt(db_, "DELETE FROM tracks WHERE id = ?").bind(1, tr->info.id).run();
    // A long live track keeps only its last retention period of fixes.
    store::Stmt(db_, "DELETE FROM track_fixes WHERE t < ?").bind(1, t - options_.retention_s).run();
    const bool trimmed = db_.changes() > 0;
    std::unordered_map<std::int64_t, std::size_t> kept;  // fixes left per track, when some were trimmed
    if (trimmed) {
        store::Stmt count(db_, "SELECT track_id, count(*) FROM track_fixes GROUP BY track_id");
        while (count.step()) kept[count.int64(0)] = static_cast<std::size_t>(count.int64(1));
    }
    std::vector<std::pair<std::int64_t, std::int64_t>> ended_here;
    for (const auto* list : {&to_close, &to_purge})
        for (const auto& tr : *list) ended_here.emplace_back(tr->info.id, tr->info.map_id);
    announce(ended_here);
    tx.commit();

    std::lock_guard lock(mu_);
    for (const auto id : ended_elsewhere) queue_refresh(id);
    for (const auto& tr : to_close) {
        tr->info.state = State::closed;
        tr->info.ended_at = t;
        tr->changed.notify_all();
        publish(tr->info, std::nullopt);
    }
    for (const auto& tr : to_purge) mark_gone(*tr, t);
    for (const auto& tr : to_forget) tracks_.erase(tr->info.id);
    std::vector<std::int64_t> ended;
    for (const auto& [id, tr] : tracks_)
        if (tr->info.state != State::live) ended.push_back(id);
    if (trimmed) {
        // Counts and latest fixes of tracks that lost old fixes: rare (a track older than the
        // retention period), so the counts are read again; without this a track posting for
        // longer than max_fixes_per_track allows would be refused as full.
        for (const auto& [id, tr] : tracks_) {
            if (tr->info.latest && tr->info.latest->t < t - options_.retention_s) tr->info.latest.reset();
            const auto left = kept.find(id);
            tr->info.fixes = left == kept.end() ? 0 : left->second;
        }
    }
    return ended;
}

void Service::sweeper() {
    const double period = std::clamp(std::min(options_.ttl_s, options_.retention_s) / 4, 0.05, 5.0);
    std::unique_lock lock(mu_);
    while (!stopping_) {
        sweep_cv_.wait_for(lock, std::chrono::duration<double>(period));
        if (stopping_) break;
        lock.unlock();
        try {
            sweep();
        } catch (const std::exception&) {
            // A storage fault now is retried at the next sweep.
        }
        lock.lock();
    }
}

}  // namespace locus::tracks
