#include "store/pg_changes.hpp"

#include <libpq-fe.h>
#include <poll.h>

#include <chrono>
#include <string_view>
#include <nlohmann/json.hpp>

#include "store/db.hpp"
#include "store/kinds.hpp"
#include "store/pg_detail.hpp"

namespace locus::store {

namespace {
// PostgreSQL refuses a NOTIFY payload of 8000 bytes or more.
constexpr std::size_t kMaxPayload = 7900;
constexpr std::string_view kTrackChannel = "locus_tracks";

nlohmann::json optional_id(const std::optional<std::int64_t>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); }
}  // namespace

std::string payload_head(const std::string& origin, const std::vector<Change>& changes) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& c : changes)
        list.push_back({c.kind ? std::string(c.kind->name) : std::string(), c.id, c.deleted, c.plan,
                        optional_id(c.radiomap_id), optional_id(c.map_id)});
    // The object without its last member, the version, which comes last in the text as it would
    // in nlohmann's (sorted) dump of the whole: {"c":…,"o":…,"v":N}.
    const auto head_of = [](const nlohmann::json& j) {
        std::string out = j.dump();
        out.pop_back();  // the closing brace
        return out + ",\"v\":";
    };
    std::string out = head_of(nlohmann::json{{"o", origin}, {"c", list}});
    // Room for the longest version (19 digits) and the closing brace.
    if (out.size() + 20 > kMaxPayload) out = head_of(nlohmann::json{{"o", origin}, {"all", true}});
    return out;
}

std::string payload_of(const std::string& origin, std::int64_t version, const std::vector<Change>& changes) {
    return payload_head(origin, changes) + std::to_string(version) + "}";
}

std::string announcement(Db& db, const std::string& origin, const std::vector<Change>& changes) {
    // One statement: the counter's next version goes into the payload there.
    return "WITH v AS (UPDATE change_counter SET version = version + 1 WHERE id = 1 RETURNING version) "
           "SELECT pg_notify('locus_changes', " +
           pg::literal(db.pg(), payload_head(origin, changes)) + " || v.version || '}') FROM v";
}

void announce_tracks(Db& db, const std::string& origin, const std::vector<Change>& changes) {
    Stmt notify(db, "SELECT pg_notify('locus_tracks', ?)");
    notify.bind(1, payload_of(origin, 0, changes)).run();
}

Change everything_changed() { return Change{&kind("maps"), 0, true, false, std::nullopt, std::nullopt}; }

Notification parse_payload(const std::string& payload) {
    const auto j = nlohmann::json::parse(payload);
    Notification n;
    n.origin = j.at("o").get<std::string>();
    n.version = j.at("v").get<std::int64_t>();
    n.everything = j.value("all", false);
    if (j.contains("c"))
        for (const auto& c : j.at("c")) {
            const auto name = c.at(0).get<std::string>();
            Change ch{name == track_kind().name ? &track_kind() : &kind(name), c.at(1).get<std::int64_t>(), c.at(2).get<bool>(),
                      c.at(3).get<bool>(), std::nullopt, std::nullopt};
            if (!c.at(4).is_null()) ch.radiomap_id = c.at(4).get<std::int64_t>();
            if (!c.at(5).is_null()) ch.map_id = c.at(5).get<std::int64_t>();
            n.changes.push_back(ch);
        }
    return n;
}

ChangeWatcher::ChangeWatcher(std::string url, std::string origin, Apply apply)
    : url_(std::move(url)), origin_(std::move(origin)), apply_(std::move(apply)) {
    thread_ = std::thread([this] { run(); });
}

ChangeWatcher::~ChangeWatcher() {
    stop_ = true;
    thread_.join();
}

namespace {
std::int64_t counter_of(PGconn* c) {
    PGresult* r = PQexec(c, "SELECT version FROM change_counter WHERE id = 1");
    if (PQresultStatus(r) != PGRES_TUPLES_OK || PQntuples(r) != 1) {
        PQclear(r);
        throw std::runtime_error("cannot read change_counter");
    }
    const std::int64_t v = std::atoll(PQgetvalue(r, 0, 0));
    PQclear(r);
    return v;
}
}  // namespace

void ChangeWatcher::run() {
    using clock = std::chrono::steady_clock;
    const std::vector<Change> everything{everything_changed()};
    while (!stop_) {
        PGconn* c = nullptr;
        try {
            c = pg::connect(url_);
            pg::exec(c, "LISTEN locus_changes");
            pg::exec(c, "LISTEN " + std::string(kTrackChannel));
        } catch (const std::exception&) {
            pg::close(c);
            for (int i = 0; i < 10 && !stop_; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
            continue;
        }
        try {
            std::int64_t seen = counter_of(c);
            // Whatever was written before LISTEN took effect was never notified here: at start (an
            // index built before this connection may already be behind) and after a lost
            // connection alike. Cheap at start, where the caches are empty or just built.
            apply_(everything);
            std::int64_t behind = -1;  // the counter at the last check, when it was ahead of `seen`
            // Every half second, so a change whose notification never came is seen within about
            // a second (ahead at two checks in a row).
            constexpr auto kCheck = std::chrono::milliseconds(500);
            auto next_check = clock::now() + kCheck;
            while (!stop_) {
                pollfd p{PQsocket(c), POLLIN, 0};
                ::poll(&p, 1, 100);
                if (!PQconsumeInput(c)) throw std::runtime_error(PQerrorMessage(c));
                while (PGnotify* n = PQnotifies(c)) {
                    Notification note;
                    bool ok = true;
                    const bool tracks = n->relname == kTrackChannel;
                    try {
                        note = parse_payload(n->extra);
                    } catch (const std::exception&) {
                        ok = false;
                    }
                    PQfreemem(n);
                    if (!ok) {
                        apply_(everything);
                        continue;
                    }
                    if (tracks) {  // not counted (announce_tracks): no version to follow
                        if (note.everything) apply_(everything);  // too many tracks for one payload
                        else if (note.origin != origin_) apply_(note.changes);
                        continue;
                    }
                    const bool gap = note.version > seen + 1;
                    if (note.version > seen) seen = note.version;
                    if (gap || note.everything) apply_(everything);
                    else if (note.origin != origin_) apply_(note.changes);
                }
                if (clock::now() >= next_check) {
                    next_check = clock::now() + kCheck;
                    const std::int64_t now = counter_of(c);
                    // Ahead at two checks in a row: its notification is not coming.
                    if (behind >= 0 && seen < behind) {
                        apply_(everything);
                        seen = now;
                    }
                    behind = now > seen ? now : -1;
                }
            }
        } catch (const std::exception&) {
            // A connection that fails at once (permissions, a dropped table) must not turn into
            // a reconnect loop against the database: wait as a failed connect does.
            for (int i = 0; i < 10 && !stop_; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        pg::close(c);
    }
}

}  // namespace locus::store
