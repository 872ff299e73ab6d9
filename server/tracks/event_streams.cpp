#include "tracks/event_streams.hpp"

#include <chrono>

#include "tracks/token.hpp"

namespace locus::tracks {

void EventStreams::publish(const TrackInfo& track, std::optional<Fix> fix) {
    map_changes_.push_back({++map_seq_, track.map_id, track.id, track.label, fix});
    if (map_changes_.size() > options_.map_event_buffer) map_changes_.pop_front();
    map_changed_.notify_all();
}

void EventStreams::mark_gone(CachedTrack& track, double t) {
    if (track.info.state == State::live) publish(track.info, std::nullopt);
    track.go(t);
}

bool EventStreams::map_watched(std::int64_t map_id) const {
    const auto it = map_streams_.find(map_id);
    return it != map_streams_.end() && it->second > 0;
}

std::vector<std::int64_t> EventStreams::watched_maps() const {
    std::vector<std::int64_t> out;
    for (const auto& [map_id, n] : map_streams_)
        if (n > 0) out.push_back(map_id);
    return out;
}

void EventStreams::wake() { map_changed_.notify_all(); }

std::size_t EventStreams::held_by(const std::optional<std::string>& client) const {
    if (!client) return 0;
    const auto it = client_streams_.find(*client);
    return it == client_streams_.end() ? 0 : it->second.size();
}

std::shared_ptr<StreamTicket> EventStreams::room_for(const std::optional<std::string>& client) const {
    if (streams_ < options_.max_streams) return nullptr;
    const std::map<std::uint64_t, std::shared_ptr<StreamTicket>>* most = nullptr;
    for (const auto& [who, held] : client_streams_)
        if (!most || held.size() > most->size()) most = &held;
    if (!most || most->size() < held_by(client) + 2)
        throw Refused(Reason::busy, "the server has " + std::to_string(streams_) + " event streams open, its most; try again later");
    return most->begin()->second;
}

void EventStreams::check_client(const std::optional<std::string>& client) const {
    const std::size_t held = held_by(client);
    if (client && held >= options_.max_streams_per_client)
        throw Refused(Reason::client_streams, "this client has " + std::to_string(held) + " event streams open, its most (--client-streams " +
                                                  std::to_string(options_.max_streams_per_client) + "); close one first");
}

std::shared_ptr<StreamTicket> EventStreams::admit(StreamTicket ticket, const std::shared_ptr<StreamTicket>& evictee) {
    if (evictee) {
        release(*evictee);
        evictee->evicted = true;
        evictee->wakes->notify_all();
    }
    auto t = std::make_shared<StreamTicket>(std::move(ticket));
    t->order = ++opened_;
    ++streams_;
    if (t->track) ++t->track->streams;
    if (t->map_id) ++map_streams_[*t->map_id];
    if (t->client) client_streams_[*t->client].emplace(t->order, t);
    return t;
}

void EventStreams::release(StreamTicket& t) {
    --streams_;
    if (t.track) --t.track->streams;
    if (t.map_id)
        if (const auto it = map_streams_.find(*t.map_id); it != map_streams_.end() && --it->second == 0) map_streams_.erase(it);
    if (t.client)
        if (const auto it = client_streams_.find(*t.client); it != client_streams_.end()) {
            it->second.erase(t.order);
            if (it->second.empty()) client_streams_.erase(it);
        }
}

TrackStreamState EventStreams::open(std::shared_ptr<CachedTrack> track, std::int64_t id, const std::optional<std::string>& client) {
    const auto evictee = room_for(client);
    if (track->streams >= options_.max_streams_per_track)
        throw Refused(Reason::too_many_streams, "track " + std::to_string(id) + " has " + std::to_string(track->streams) +
                                                    " event streams open, its most; close one first");
    check_client(client);
    TrackStreamState s;
    s.seen = track->seq;
    s.client = client;
    s.ticket = admit({client, 0, track, std::nullopt, &track->changed, false}, evictee);
    s.track = std::move(track);
    return s;
}

void EventStreams::close(TrackStreamState& s) {
    std::lock_guard lock(cache_.mutex());
    if (!s.ticket->evicted) release(*s.ticket);
}

Events EventStreams::next(TrackStreamState& s, double wait_s) {
    std::unique_lock lock(cache_.mutex());
    CachedTrack& t = *s.track;
    Events out;
    const auto revoked = [&] {
        if (!s.share_hash) return false;
        for (const auto& [share_id, share_hash] : t.shares)
            if (same_hash(*s.share_hash, share_hash)) return false;
        return true;
    };
    if (!s.started) {
        s.started = true;
        // The latest fix stands for any stored since the stream opened: none is given twice.
        if (t.info.latest) out.fixes.push_back(*t.info.latest);
        s.seen = t.seq;
    } else {
        t.changed.wait_for(lock, std::chrono::duration<double>(wait_s), [&] {
            return t.seq > s.seen || t.info.state != State::live || cache_.stopping() || revoked() || s.ticket->evicted;
        });
        for (const auto& [seq, fix] : t.recent)
            if (seq > s.seen) out.fixes.push_back(fix);
        s.seen = t.seq;
    }
    if (revoked()) out.fixes.clear();  // a revoked reader is told nothing more
    out.evicted = s.ticket->evicted;
    out.ended = t.info.state != State::live || cache_.stopping() || revoked() || out.evicted;
    return out;
}

MapStreamState EventStreams::open_map(std::int64_t map_id, std::optional<std::int64_t> floor_id, const std::optional<std::string>& client) {
    const auto evictee = room_for(client);
    check_client(client);
    MapStreamState s;
    s.map_id = map_id;
    s.floor_id = floor_id;
    s.client = client;
    s.ticket = admit({client, 0, nullptr, map_id, &map_changed_, false}, evictee);
    return s;
}

void EventStreams::close(MapStreamState& s) {
    std::lock_guard lock(cache_.mutex());
    if (!s.ticket->evicted) release(*s.ticket);
}

MapEvents EventStreams::next(MapStreamState& s, double wait_s) {
    MapEvents out;
    if (!s.started) {
        // The sequence is read before the snapshot: a change between the two is written twice
        // (positions are idempotent), never lost.
        {
            std::lock_guard lock(cache_.mutex());
            s.seen = map_seq_;
        }
        const auto now_live = cache_.live_on_map(s.map_id, s.floor_id);
        s.started = true;
        for (const auto& t : now_live) {
            out.events.push_back({MapEvent::Kind::position, t.id, t.label, t.latest});
            s.shown.insert(t.id);
        }
        std::lock_guard lock(cache_.mutex());
        out.evicted = s.ticket->evicted;
        out.ended = cache_.stopping() || out.evicted;
        return out;
    }
    std::unique_lock lock(cache_.mutex());
    map_changed_.wait_for(lock, std::chrono::duration<double>(wait_s),
                          [&] { return map_seq_ > s.seen || cache_.stopping() || s.ticket->evicted; });
    // A stream that fell more than map_event_buffer changes behind misses the oldest: the next
    // fix of each track shows it again.
    for (const auto& c : map_changes_) {
        if (c.seq <= s.seen || c.map_id != s.map_id) continue;
        if (c.fix && (!s.floor_id || c.fix->floor_id == *s.floor_id)) {
            out.events.push_back({MapEvent::Kind::position, c.track_id, c.label, c.fix});
            s.shown.insert(c.track_id);
        } else if (s.shown.erase(c.track_id)) {
            out.events.push_back({MapEvent::Kind::leave, c.track_id, c.label, c.fix});
        }
    }
    s.seen = map_seq_;
    out.evicted = s.ticket->evicted;
    out.ended = cache_.stopping() || out.evicted;
    return out;
}

}  // namespace locus::tracks
