#include "store/track_repository.hpp"

#include <algorithm>

#include "store/kinds.hpp"
#include "store/pg_changes.hpp"

namespace locus::store {

namespace {

FixRow fix_of(Stmt& q, int c) {
    FixRow f;
    f.t = q.real(c);
    f.floor_id = q.int64(c + 1);
    f.x = q.real(c + 2);
    f.y = q.real(c + 3);
    f.accuracy_m = q.real(c + 4);
    if (!q.is_null(c + 5)) f.heading_deg = q.real(c + 5);
    return f;
}

// The columns after id, from column `c` on: map_id, label, token_hash, state, created_at,
// last_fix_at, ended_at, fusion, fusion_options.
TrackRow track_of(Stmt& q, std::int64_t id, int c) {
    TrackRow t;
    t.id = id;
    if (!q.is_null(c)) t.map_id = q.int64(c);
    t.label = q.is_null(c + 1) ? "" : q.text(c + 1);
    t.token_hash = q.blob(c + 2);
    t.state = q.text(c + 3);
    t.created_at = q.real(c + 4);
    t.last_fix_at = q.real(c + 5);
    if (!q.is_null(c + 6)) t.ended_at = q.real(c + 6);
    t.fusion = q.text(c + 7);
    if (!q.is_null(c + 8)) t.fusion_options = q.text(c + 8);
    return t;
}

}  // namespace

TrackRepository::TrackRepository(const std::string& connection, std::string origin) : db_(connection), origin_(std::move(origin)) {}

std::vector<TrackRow> TrackRepository::tracks() {
    std::vector<TrackRow> out;
    Stmt q(db_, "SELECT id, map_id, label, token_hash, state, created_at, last_fix_at, ended_at, fusion, fusion_options FROM tracks");
    while (q.step()) out.push_back(track_of(q, q.int64(0), 1));
    return out;
}

std::vector<LatestFixRow> TrackRepository::latest_fixes() {
    std::vector<LatestFixRow> out;
    Stmt q(db_,
           "SELECT track_id, t, floor_id, x, y, accuracy_m, heading_deg, n FROM "
           "(SELECT track_id, t, floor_id, x, y, accuracy_m, heading_deg, "
           "row_number() OVER (PARTITION BY track_id ORDER BY t DESC) AS r, "
           "count(*) OVER (PARTITION BY track_id) AS n FROM track_fixes) AS latest WHERE r = 1");
    while (q.step()) out.push_back({q.int64(0), fix_of(q, 1), static_cast<std::size_t>(q.int64(7))});
    return out;
}

std::vector<ShareRow> TrackRepository::shares() {
    std::vector<ShareRow> out;
    Stmt q(db_, "SELECT id, track_id, token_hash FROM track_shares");
    while (q.step()) out.push_back({q.int64(0), q.int64(1), q.blob(2)});
    return out;
}

std::optional<TrackRow> TrackRepository::track(std::int64_t id) {
    Stmt q(db_, "SELECT map_id, label, token_hash, state, created_at, last_fix_at, ended_at, fusion, fusion_options FROM tracks WHERE id = ?");
    q.bind(1, id);
    if (!q.step()) return std::nullopt;
    return track_of(q, id, 0);
}

bool TrackRepository::map_exists(std::int64_t map_id) {
    Stmt m(db_, "SELECT 1 FROM maps WHERE id = ?");
    m.bind(1, map_id);
    return m.step();
}

std::optional<FixRow> TrackRepository::latest_fix(std::int64_t id) {
    Stmt q(db_, "SELECT t, floor_id, x, y, accuracy_m, heading_deg FROM track_fixes WHERE track_id = ? ORDER BY t DESC LIMIT 1");
    q.bind(1, id);
    if (!q.step()) return std::nullopt;
    return fix_of(q, 0);
}

std::vector<FixRow> TrackRepository::last_fixes(std::int64_t id, std::optional<double> after, std::size_t limit) {
    Stmt q(db_, after ? "SELECT t, floor_id, x, y, accuracy_m, heading_deg FROM track_fixes WHERE track_id = ? AND t > ? ORDER BY t DESC LIMIT ?"
                      : "SELECT t, floor_id, x, y, accuracy_m, heading_deg FROM track_fixes WHERE track_id = ? ORDER BY t DESC LIMIT ?");
    q.bind(1, id);
    if (after) q.bind(2, *after).bind(3, limit);
    else q.bind(2, limit);
    std::vector<FixRow> out;
    while (q.step()) out.push_back(fix_of(q, 0));
    std::reverse(out.begin(), out.end());
    return out;
}

std::size_t TrackRepository::fix_count(std::int64_t id) {
    Stmt count(db_, "SELECT count(*) FROM track_fixes WHERE track_id = ?");
    count.bind(1, id);
    count.step();
    return static_cast<std::size_t>(count.int64(0));
}

std::map<std::int64_t, std::string> TrackRepository::shares_of(std::int64_t id) {
    std::map<std::int64_t, std::string> out;
    Stmt sh(db_, "SELECT id, token_hash FROM track_shares WHERE track_id = ?");
    sh.bind(1, id);
    while (sh.step()) out[sh.int64(0)] = sh.blob(1);
    return out;
}

std::vector<std::int64_t> TrackRepository::live_on_map(std::int64_t map_id) {
    std::vector<std::int64_t> out;
    Stmt q(db_, "SELECT id FROM tracks WHERE map_id = ? AND state = 'live'");
    q.bind(1, map_id);
    while (q.step()) out.push_back(q.int64(0));
    return out;
}

std::optional<double> TrackRepository::live_last_fix_at(std::int64_t id) {
    Stmt last(db_, "SELECT last_fix_at FROM tracks WHERE id = ? AND state = 'live'");
    last.bind(1, id);
    if (!last.step()) return std::nullopt;
    return last.real(0);
}

ClientTracks TrackRepository::client_tracks(const std::string& client_hash, double since) {
    // Replicas count in one order: two opens of one client on two servers cannot both
    // see room for one more. Any constant: the lock only serializes these counts.
    if (db_.is_postgres()) db_.exec("SELECT pg_advisory_xact_lock(7343469)");
    Stmt q(db_, "SELECT count(*), min(last_fix_at) FROM tracks WHERE client_hash = ? AND state = 'live' AND last_fix_at >= ?");
    q.bind_blob(1, client_hash).bind(2, since);
    q.step();
    return {static_cast<std::size_t>(q.int64(0)), q.is_null(1) ? 0.0 : q.real(1)};  // none live: no minimum
}

std::int64_t TrackRepository::insert(const NewTrackRow& row) {
    Stmt ins(db_, "INSERT INTO tracks (map_id, label, token_hash, state, created_at, last_fix_at, fusion, fusion_options, client_hash) "
                  "VALUES (?, ?, ?, 'live', ?, ?, ?, ?, ?)");
    ins.bind(1, row.map_id);
    if (row.label.empty()) ins.bind_null(2);
    else ins.bind(2, std::string_view(row.label));
    ins.bind_blob(3, row.token_hash).bind(4, row.t).bind(5, row.t).bind(6, std::string_view(row.fusion));
    if (row.fusion_options.empty()) ins.bind_null(7);
    else ins.bind(7, std::string_view(row.fusion_options));
    if (row.client_hash.empty()) ins.bind_null(8);
    else ins.bind_blob(8, row.client_hash);
    ins.run();
    return db_.last_insert_id();
}

std::vector<std::size_t> TrackRepository::insert_fixes(std::int64_t id, const std::vector<FixRow>& fixes) {
    std::vector<std::size_t> stored;
    Stmt ins(db_, "INSERT OR IGNORE INTO track_fixes (track_id, t, floor_id, x, y, accuracy_m, heading_deg) VALUES (?, ?, ?, ?, ?, ?, ?)");
    for (std::size_t i = 0; i < fixes.size(); ++i) {
        const auto& f = fixes[i];
        ins.bind(1, id).bind(2, f.t).bind(3, f.floor_id).bind(4, f.x).bind(5, f.y).bind(6, f.accuracy_m);
        if (f.heading_deg) ins.bind(7, *f.heading_deg);
        else ins.bind_null(7);
        ins.run();
        if (db_.changes() == 1) stored.push_back(i);
        ins.reset();
    }
    return stored;
}

void TrackRepository::touch(std::int64_t id, double t) {
    Stmt(db_, "UPDATE tracks SET last_fix_at = ? WHERE id = ?").bind(1, t).bind(2, id).run();
}

void TrackRepository::close(std::int64_t id, double t) {
    Stmt(db_, "UPDATE tracks SET state = 'closed', ended_at = ?, client_hash = NULL WHERE id = ?").bind(1, t).bind(2, id).run();
}

void TrackRepository::remove(std::int64_t id, double t) {
    Stmt(db_, "DELETE FROM track_fixes WHERE track_id = ?").bind(1, id).run();
    Stmt(db_, "DELETE FROM track_shares WHERE track_id = ?").bind(1, id).run();
    Stmt(db_, "UPDATE tracks SET state = 'gone', map_id = NULL, label = NULL, ended_at = ?, client_hash = NULL WHERE id = ?")
        .bind(1, t)
        .bind(2, id)
        .run();
}

void TrackRepository::purge(std::int64_t id, double t) {
    Stmt(db_, "DELETE FROM track_fixes WHERE track_id = ?").bind(1, id).run();
    Stmt(db_, "DELETE FROM track_shares WHERE track_id = ?").bind(1, id).run();
    Stmt(db_, "UPDATE tracks SET state = 'gone', map_id = NULL, label = NULL, ended_at = ? WHERE id = ?").bind(1, t).bind(2, id).run();
}

void TrackRepository::forget(std::int64_t id) { Stmt(db_, "DELETE FROM tracks WHERE id = ?").bind(1, id).run(); }

void TrackRepository::drop(std::int64_t id) {
    Stmt(db_, "DELETE FROM track_fixes WHERE track_id = ?").bind(1, id).run();
    Stmt(db_, "DELETE FROM track_shares WHERE track_id = ?").bind(1, id).run();
    Stmt(db_, "DELETE FROM tracks WHERE id = ?").bind(1, id).run();
}

bool TrackRepository::trim_fixes(double before) {
    Stmt(db_, "DELETE FROM track_fixes WHERE t < ?").bind(1, before).run();
    return db_.changes() > 0;
}

std::unordered_map<std::int64_t, std::size_t> TrackRepository::fix_counts() {
    std::unordered_map<std::int64_t, std::size_t> out;
    Stmt count(db_, "SELECT track_id, count(*) FROM track_fixes GROUP BY track_id");
    while (count.step()) out[count.int64(0)] = static_cast<std::size_t>(count.int64(1));
    return out;
}

std::int64_t TrackRepository::add_share(std::int64_t id, const std::string& token_hash, double t) {
    Stmt ins(db_, "INSERT INTO track_shares (track_id, token_hash, created_at) VALUES (?, ?, ?)");
    ins.bind(1, id).bind_blob(2, token_hash).bind(3, t).run();
    return db_.last_insert_id();
}

void TrackRepository::remove_share(std::int64_t share_id) { Stmt(db_, "DELETE FROM track_shares WHERE id = ?").bind(1, share_id).run(); }

void TrackRepository::announce(const std::vector<std::pair<std::int64_t, std::int64_t>>& tracks) {
    if (origin_.empty() || tracks.empty()) return;
    std::vector<Change> changes;
    for (const auto& [id, map_id] : tracks) changes.push_back(Change{&track_kind(), id, false, false, std::nullopt, map_id});
    // A notification of many changes would pass PostgreSQL's payload limit and be sent as
    // "everything changed", dropping every server's caches: a sweep closing many tracks sends several.
    constexpr std::size_t kPerNotification = 50;
    for (std::size_t i = 0; i < changes.size(); i += kPerNotification) {
        const auto end = changes.begin() + static_cast<std::ptrdiff_t>(std::min(changes.size(), i + kPerNotification));
        announce_tracks(db_, origin_, std::vector<Change>(changes.begin() + static_cast<std::ptrdiff_t>(i), end));
    }
}

}  // namespace locus::store
