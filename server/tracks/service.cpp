#include "tracks/service.hpp"

#include <algorithm>
#include <chrono>

#include "store/kinds.hpp"
#include "tracks/fusion.hpp"
#include "tracks/token.hpp"
#include "tracks/track_rows.hpp"

namespace locus::tracks {

const char* state_name(State s) {
    switch (s) {
        case State::live: return "live";
        case State::closed: return "closed";
        case State::gone: return "gone";
    }
    return "live";
}

double Service::now() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

Service::Service(store::Store& store, Options options)
    : store_(store), options_(options), repo_(store.connection(), store.change_origin()) {
    if (options_.client_key.empty()) options_.client_key = token_hash(new_token("key_"));
    {
        std::lock_guard db_lock(repo_.mutex());
        cache_.load(repo_);
    }
    subscription_ = store_.subscribe([this](const store::Change& c) { on_change(c); });
    sweeper_.start([this] { sweep(); });
    replication_.start();
}

void Service::on_change(const store::Change& c) {
    if (c.kind == &store::track_kind()) {
        replication_.on_track_change(c.id, c.map_id);
        return;
    }
    if (c.plan || (c.kind && c.kind->name == "floors")) fusions_.floor_changed(c.id);
    // A deleted map took its floors by cascade, without a change each; it is also how
    // another server's "everything changed" arrives (store/pg_changes.hpp): drop them all.
    if (!c.plan && c.deleted && c.kind && c.kind->name == "maps") fusions_.all_floors_changed();
    // A floor, building or map deleted or moved: which floors are on which map is asked again.
    if (!c.plan && c.kind && (c.kind->name == "floors" || c.kind->name == "buildings" || c.kind->name == "maps")) {
        std::lock_guard lock(cache_.mutex());
        cache_.forget_floors();
    }
    if (!c.plan && c.deleted && c.kind && c.kind->name == "maps") map_deleted(c.id);
    // "Everything changed" (a map id 0 cannot be deleted otherwise): notifications of other
    // servers' track writes may have been missed too.
    if (!c.plan && c.deleted && c.kind && c.kind->name == "maps" && c.id == 0) {
        std::lock_guard lock(cache_.mutex());
        replication_.catch_up_later();
    }
}

Service::~Service() {
    store_.unsubscribe(subscription_);
    stop();
    sweeper_.join();
    replication_.join();
}

void Service::stop() {
    std::lock_guard lock(cache_.mutex());
    cache_.stop();
    sweeper_.wake();
    replication_.wake();
    streams_.wake();
}

void Service::map_deleted(std::int64_t map_id) {
    const double t = now();
    std::lock_guard lock(cache_.mutex());
    for (const auto& [id, track] : cache_.all())
        if (track->info.map_id == map_id && track->info.state != State::gone) streams_.mark_gone(*track, t);
}

Opened Service::open(std::int64_t map_id, const std::string& label, FusionMethod fusion, const FusionOptions& options,
                     const std::optional<std::string>& client) {
    (void)store_.get(store::kind("maps"), map_id);  // NotFound for an unknown map
    Opened out;
    out.token = new_token("trk_");
    const std::string hash = token_hash(out.token);
    const double t = now();
    std::vector<std::shared_ptr<CachedTrack>> evicted;
    {
        std::lock_guard db_lock(repo_.mutex());
        {
            std::lock_guard lock(cache_.mutex());
            const auto live = cache_.live();
            if (live >= options_.max_live_tracks)
                throw Refused(Reason::busy, "the server follows " + std::to_string(live) + " live tracks, its most; try again later");
            // Closed tracks and tombstones give way to a live one: an anonymous loop of opens
            // and deletes (or closes) must not refuse everyone else's opens for a retention period.
            if (cache_.size() >= options_.max_tracks) {
                const std::size_t over = cache_.size() + 1 - options_.max_tracks;
                evicted = sweeper_.evictable(over);
                if (evicted.size() < over)
                    throw Refused(Reason::too_many_tracks, "the server follows " + std::to_string(live) +
                                                               " live tracks, as many as it holds at all (--max-tracks); try again later");
            }
        }
        out.info = insert_track(map_id, label, fusion, options, hash, t, evicted, client ? keyed_hash(options_.client_key, *client) : "");
    }
    // With no other lock held: post_raw takes a track's run lock, then the sessions' (briefly),
    // then these. Only when something was evicted, so that an open does not wait for a floor's
    // first Walkable to be built.
    if (!evicted.empty()) {
        std::vector<std::int64_t> ids;
        for (const auto& tr : evicted) ids.push_back(tr->info.id);
        fusions_.forget(ids);
    }
    return out;
}

TrackInfo Service::insert_track(std::int64_t map_id, const std::string& label, FusionMethod fusion, const FusionOptions& options,
                                const std::string& hash, double t, const std::vector<std::shared_ptr<CachedTrack>>& evicted,
                                const std::string& client_hash) {
    store::TrackRepository::Write tx(repo_);
    if (!client_hash.empty()) {
        // A live track past --track-ttl that no sweeper closed yet (its server died) holds nothing.
        const auto held = repo_.client_tracks(client_hash, t - options_.ttl_s);
        // The client's next track frees when its quietest one reaches --track-ttl without a fix.
        if (held.held >= options_.max_live_tracks_per_client)
            throw Refused(Reason::client_live_tracks,
                          "this client holds " + std::to_string(held.held) + " live tracks, its most (--client-live-tracks " +
                              std::to_string(options_.max_live_tracks_per_client) + "); close one first",
                          std::max(1.0, held.quietest_last_fix_at + options_.ttl_s - t));
    }
    for (const auto& tr : evicted) repo_.drop(tr->info.id);
    const std::int64_t id =
        repo_.insert({map_id, label, hash, t, fusion_method_stored_name(fusion), fusion_options_text(options), client_hash});
    tx.commit();
    auto track = std::make_shared<CachedTrack>();
    track->info = {id, map_id, label, State::live, t, t, std::nullopt, std::nullopt, 0, fusion, options};
    track->token_hash = hash;
    std::lock_guard lock(cache_.mutex());
    for (const auto& tr : evicted) {
        if (tr->info.state != State::gone) streams_.mark_gone(*tr, t);  // its streams end
        cache_.erase(tr->info.id);
    }
    cache_.slot(id) = track;
    return track->info;
}

Access Service::authorize(std::int64_t id, const std::string& token) {
    if (repo_.is_postgres()) replication_.refresh(id);
    const std::string hash = token_hash(token);
    std::lock_guard lock(cache_.mutex());
    const auto t = cache_.find(id);
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
        std::lock_guard lock(cache_.mutex());
        map_id = cache_.find(id)->info.map_id;
        const auto& known = cache_.floors_of(map_id);
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
        std::lock_guard lock(cache_.mutex());
        cache_.floors_of(map_id).insert(floor_id);
    }
    return std::nullopt;
}

Posted Service::post(std::int64_t id, const std::vector<Fix>& fixes) {
    const double t_now = now();
    std::lock_guard db_lock(repo_.mutex());  // held to the end: two posts of one track publish in commit order
    std::shared_ptr<CachedTrack> track;
    std::int64_t map_id = 0;
    {
        std::lock_guard lock(cache_.mutex());
        track = cache_.find(id);
        map_id = track->info.map_id;
        if (track->info.state != State::live)
            throw Refused(Reason::closed, "track " + std::to_string(id) + " is " + state_name(track->info.state) + "; open a new one");
        if (track->info.fixes + fixes.size() > options_.max_fixes_per_track)
            throw Refused(Reason::full, "track " + std::to_string(id) + " holds " + std::to_string(track->info.fixes) +
                                            " fixes; at most " + std::to_string(options_.max_fixes_per_track) + " are kept: open a new track");
    }
    Posted out;
    std::vector<Fix> stored;
    store::TrackRepository::Write tx(repo_);
    std::vector<store::FixRow> rows;
    rows.reserve(fixes.size());
    for (const auto& f : fixes) rows.push_back(row_of(f));
    for (const auto i : repo_.insert_fixes(id, rows)) stored.push_back(fixes[i]);
    repo_.touch(id, t_now);
    if (!stored.empty()) repo_.announce({{id, map_id}});
    tx.commit();

    std::lock_guard lock(cache_.mutex());
    track->info.last_fix_at = t_now;
    track->info.fixes += stored.size();
    const auto before = track->info.latest;
    for (const auto& f : stored) {
        if (!track->info.latest || f.t > track->info.latest->t) track->info.latest = f;
        track->remember(f, options_.event_buffer);
    }
    if (!stored.empty()) track->changed.notify_all();
    if (track->info.latest && (!before || before->t != track->info.latest->t)) streams_.publish(track->info, track->info.latest);
    out.stored = stored.size();
    out.duplicates = fixes.size() - stored.size();
    out.latest = track->info.latest;
    return out;
}

std::pair<Posted, std::vector<Fix>> Service::post_raw(std::int64_t id, const std::vector<Step>& steps, const std::vector<RadioFix>& radio,
                                                     const std::vector<Pressure>& pressure, const std::vector<Gnss>& gnss,
                                                     std::shared_ptr<const FloorAnchors> anchors, RunSources* sources) {
    auto run = fusions_.begin(id);
    FusionMethod method;
    FusionOptions options;
    std::optional<Fix> latest;
    {
        std::lock_guard lock(cache_.mutex());
        const auto& track = cache_.find(id);
        if (track->info.state != State::live)
            throw Refused(Reason::closed, "track " + std::to_string(id) + " is not live; open a new one");
        method = track->info.fusion;
        options = track->info.fusion_options;
        latest = track->info.latest;
    }
    std::vector<Fix> fused = run.run(method, options, latest, steps, radio, pressure, gnss, std::move(anchors), sources);
    // A radio fix and a step at one t give two fixes: the track keeps the later state. A t
    // stored by an earlier request (a retry) keeps the first fix, as posted fixes do.
    std::vector<Fix> kept;
    for (const Fix& f : fused) {
        if (!kept.empty() && kept.back().t == f.t) kept.back() = f;
        else kept.push_back(f);
    }
    Posted posted = post(id, kept);
    run.keep();
    return {posted, std::move(fused)};
}

TrackInfo Service::close(std::int64_t id) {
    const double t = now();
    std::lock_guard db_lock(repo_.mutex());
    std::shared_ptr<CachedTrack> track;
    std::int64_t map_id = 0;
    {
        std::lock_guard lock(cache_.mutex());
        track = cache_.find(id);
        map_id = track->info.map_id;
        if (track->info.state != State::live) return track->info;  // closing twice is closing once
    }
    store::TrackRepository::Write tx(repo_);
    repo_.close(id, t);
    repo_.announce({{id, map_id}});
    tx.commit();
    std::lock_guard lock(cache_.mutex());
    track->info.state = State::closed;
    track->info.ended_at = t;
    track->changed.notify_all();
    streams_.publish(track->info, std::nullopt);
    return track->info;
}

void Service::remove(std::int64_t id) {
    const double t = now();
    std::lock_guard db_lock(repo_.mutex());
    std::shared_ptr<CachedTrack> track;
    std::int64_t map_id = 0;
    {
        std::lock_guard lock(cache_.mutex());
        track = cache_.find(id);
        map_id = track->info.map_id;
    }
    store::TrackRepository::Write tx(repo_);
    repo_.remove(id, t);
    repo_.announce({{id, map_id}});
    tx.commit();
    std::lock_guard lock(cache_.mutex());
    streams_.mark_gone(*track, t);
}

TrackInfo Service::info(std::int64_t id) const {
    std::lock_guard lock(cache_.mutex());
    return cache_.find(id)->info;
}

std::vector<Fix> Service::trail(std::int64_t id, std::size_t limit) {
    std::lock_guard db_lock(repo_.mutex());
    std::vector<Fix> out;
    for (const auto& f : repo_.last_fixes(id, std::nullopt, limit)) out.push_back(fix_of(f));
    return out;
}

std::vector<TrackInfo> Service::live_on_map(std::int64_t map_id, std::optional<std::int64_t> floor_id) const {
    return cache_.live_on_map(map_id, floor_id);
}

Share Service::add_share(std::int64_t id) {
    Share out;
    out.track_id = id;
    out.token = new_token("shr_");
    const std::string hash = token_hash(out.token);
    std::lock_guard db_lock(repo_.mutex());
    std::shared_ptr<CachedTrack> track;
    {
        std::lock_guard lock(cache_.mutex());
        track = cache_.find(id);
        if (track->info.state != State::live)
            throw Refused(Reason::closed, "track " + std::to_string(id) + " is " + state_name(track->info.state) + ": there is nothing to share");
        if (track->shares.size() >= 100) throw Refused(Reason::full, "track " + std::to_string(id) + " has 100 shares, its most; revoke one first");
    }
    out.id = repo_.add_share(id, hash, now());
    std::lock_guard lock(cache_.mutex());
    track->shares[out.id] = hash;
    return out;
}

void Service::revoke_share(std::int64_t id, std::int64_t share_id) {
    std::lock_guard db_lock(repo_.mutex());
    std::shared_ptr<CachedTrack> track;
    std::int64_t map_id = 0;
    {
        std::lock_guard lock(cache_.mutex());
        track = cache_.find(id);
        map_id = track->info.map_id;
        if (!track->shares.contains(share_id))
            throw store::NotFound("track " + std::to_string(id) + " has no share " + std::to_string(share_id));
    }
    store::TrackRepository::Write tx(repo_);
    repo_.remove_share(share_id);
    repo_.announce({{id, map_id}});
    tx.commit();
    std::lock_guard lock(cache_.mutex());
    track->shares.erase(share_id);
    track->changed.notify_all();  // its open streams end now
}

Service::Stream::~Stream() { streams_.close(state_); }

std::unique_ptr<Service::Stream> Service::open_stream(std::int64_t id, const std::string& token, const std::optional<std::string>& client) {
    const bool shared = authorize(id, token) == Access::share;
    std::lock_guard lock(cache_.mutex());
    auto track = cache_.find(id);
    std::unique_ptr<Stream> s(new Stream(streams_, streams_.open(track, id, client)));
    if (shared) s->state_.share_hash = token_hash(token);
    // authorize() read the database before this stream was counted: another server's change
    // notified in between found no stream caring and was dropped. Read again now it counts.
    replication_.queue_refresh(id);
    return s;
}

Events Service::next_events(Stream& stream, double wait_s) { return streams_.next(stream.state_, wait_s); }

Service::MapStream::~MapStream() { streams_.close(state_); }

std::unique_ptr<Service::MapStream> Service::open_map_stream(std::int64_t map_id, std::optional<std::int64_t> floor_id,
                                                             const std::optional<std::string>& client) {
    std::lock_guard lock(cache_.mutex());
    std::unique_ptr<MapStream> s(new MapStream(streams_, streams_.open_map(map_id, floor_id, client)));
    // Other servers' tracks on the map, as the database holds them now, read on the
    // refresher's thread: a request thread neither waits for their round trips nor fails
    // when PostgreSQL is away (retried there). Each arrives as a position; their later
    // changes come on the feed (Replication::on_track_change).
    replication_.catch_up_map_later(map_id);
    return s;
}

MapEvents Service::next_map_events(MapStream& stream, double wait_s) { return streams_.next(stream.state_, wait_s); }

void Service::sweep() {
    fusions_.forget(sweeper_.sweep());  // with no other lock held: post_raw takes the sessions' first
}

}  // namespace locus::tracks
