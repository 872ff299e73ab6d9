// Event streams across servers sharing one PostgreSQL database: a fix, a close, a revoked share
// or a deleted track on server A reaches the track and positions streams open on server B
// promptly, in order and once each, as if it had happened on B; a change whose notification
// never came is caught up too; and a thin client's steps track fuses as on one server. Runs
// only under scripts/with_postgres.sh (LOCUS_TEST_DB_URL); an SQLite file has one server.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "sse_listener.hpp"
#include "test_database.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_replica_events_test {
namespace {

// How long a stream on B may take to show a change made on A (a notification, then B's read of
// the change): the wait ends at the event, so only a failure waits this long. Generous, as the
// suite runs four tests at a time on two cores.
constexpr double kReach = 10.0;

using locus::testing::body_of;
using locus::testing::open_track;
using locus::testing::SameDatabase;
using locus::testing::ServerProcess;
using locus::testing::Track;
using locus::testing::track_call;
using locus::testing::unix_now;
using nlohmann::json;

json fix(double t, std::int64_t floor, double x) { return {{"t", t}, {"floor_id", floor}, {"x", x}, {"y", 1.0}, {"accuracy_m", 1.5}}; }

void post_fixes(const ServerProcess& s, const Track& t, const json& fixes) {
    const auto r = track_call(s, "POST", t.path("/fixes"), {t.token}, json{{"fixes", fixes}}.dump());
    ASSERT_EQ(r.status, 200) << r.raw;
}

// A stream read with the track's token (none: the positions stream, open on a keyless server).
struct Listener : locus::testing::SseListener {
    Listener(int port, const std::string& path, const std::string& track_token)
        : SseListener(port, path, track_token.empty() ? httplib::Headers{} : httplib::Headers{{"X-Track-Token", track_token}}) {}
};

std::vector<double> fix_times(const std::vector<std::pair<std::string, json>>& events) {
    std::vector<double> out;
    for (const auto& [name, data] : events)
        if (name == "fix") out.push_back(data.at("t").get<double>());
    return out;
}

Track open_with_fix(const ServerProcess& a, const locus::testing::Hierarchy& h, const std::string& label, double t) {
    const Track out = open_track(a, {{"map_id", h.map}, {"label", label}});
    post_fixes(a, out, json::array({fix(t, h.floor, 0)}));
    return out;
}

// On A: a hierarchy and a track `label` with one fix `age_s` ago; on B: the track's stream and
// the map's positions stream, opened after that fix.
struct Followed {
    locus::testing::Hierarchy h;
    double t0;
    Track t;
    Listener track_stream, map_stream;

    Followed(const ServerProcess& a, const ServerProcess& b, const std::string& label, double age_s)
        : h(locus::testing::make_hierarchy(a)),
          t0(unix_now() - age_s),
          t(open_with_fix(a, h, label, t0)),
          track_stream(b.port(), t.path("/events"), t.token),
          map_stream(b.port(), "/v1/maps/" + std::to_string(h.map) + "/positions/events", "") {}
};

struct ReplicaEvents : ::testing::Test {
    void SetUp() override {
        if (!locus::testing::on_postgres())
            GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)";
        a = std::make_unique<ServerProcess>(std::vector<std::string>{"--quiet", "--track-heartbeat", "0.2"});
        b = std::make_unique<ServerProcess>(std::vector<std::string>{"--quiet", "--track-heartbeat", "0.2"}, SameDatabase{a->db()});
    }
    void TearDown() override {
        b.reset();  // before a, whose database it uses
        a.reset();
    }
    std::unique_ptr<ServerProcess> a, b;
};

TEST_F(ReplicaEvents, FixesPostedOnOneServerReachTheOthersStreamsInOrderOnceEach) {
    Followed f(*a, *b, "ann", 60);
    ASSERT_TRUE(f.track_stream.wait_for(1, kReach));
    ASSERT_TRUE(f.map_stream.wait_for(1, kReach));
    EXPECT_EQ(f.map_stream.seen()[0].second.at("fix").at("x"), 0.0);

    // One fix at a time, each seen on B within a second; then a batch of three.
    std::vector<double> want = {f.t0};
    for (int i = 1; i <= 4; ++i) {
        const auto posted = std::chrono::steady_clock::now();
        post_fixes(*a, f.t, json::array({fix(f.t0 + i, f.h.floor, i)}));
        want.push_back(f.t0 + i);
        ASSERT_TRUE(f.track_stream.wait_for(want.size(), kReach)) << "fix " << i << " did not reach B's track stream";
        ASSERT_TRUE(f.map_stream.wait_for(1 + static_cast<std::size_t>(i), kReach)) << "fix " << i << " did not reach B's positions stream";
        EXPECT_LT(std::chrono::steady_clock::now() - posted, std::chrono::seconds(1));
        const auto last = f.map_stream.seen().back();
        EXPECT_EQ(last.first, "position");
        EXPECT_EQ(last.second.at("track_id"), f.t.id);
        EXPECT_EQ(last.second.at("label"), "ann");
        EXPECT_EQ(last.second.at("fix").at("x").get<double>(), i);
    }
    post_fixes(*a, f.t, json::array({fix(f.t0 + 5, f.h.floor, 5), fix(f.t0 + 6, f.h.floor, 6), fix(f.t0 + 7, f.h.floor, 7)}));
    for (int i = 5; i <= 7; ++i) want.push_back(f.t0 + i);
    ASSERT_TRUE(f.track_stream.wait_for(want.size(), kReach));
    ASSERT_TRUE(f.map_stream.wait_for(6, kReach));
    // A retry of fixes already stored (on either server) is no event anywhere.
    post_fixes(*b, f.t, json::array({fix(f.t0 + 7, f.h.floor, 7)}));
    post_fixes(*a, f.t, json::array({fix(f.t0 + 6, f.h.floor, 6)}));
    std::this_thread::sleep_for(std::chrono::milliseconds(600));  // heartbeats only: nothing repeated
    EXPECT_EQ(fix_times(f.track_stream.seen()), want);
    EXPECT_EQ(f.map_stream.seen().size(), 6u);
    EXPECT_EQ(f.map_stream.seen().back().second.at("fix").at("x"), 7.0);
    // A fix posted to B itself still comes once.
    post_fixes(*b, f.t, json::array({fix(f.t0 + 8, f.h.floor, 8)}));
    want.push_back(f.t0 + 8);
    ASSERT_TRUE(f.track_stream.wait_for(want.size(), kReach));

    // Closed on A: B's track stream ends as on a local close, and the track leaves B's map stream.
    ASSERT_EQ(track_call(*a, "POST", f.t.path("/close"), {f.t.token}, "{}").status, 200);
    EXPECT_TRUE(f.track_stream.ended(1.0)) << "B's track stream did not end when A closed the track";
    ASSERT_TRUE(f.map_stream.wait_for(8, kReach));
    EXPECT_EQ(f.map_stream.seen().back().first, "leave");
    EXPECT_EQ(f.map_stream.seen().back().second.at("track_id"), f.t.id);
    EXPECT_TRUE(f.map_stream.seen().back().second.at("floor_id").is_null());
    EXPECT_EQ(fix_times(f.track_stream.seen()), want);
}

TEST_F(ReplicaEvents, ATrackOpenedOnOneServerAppearsOnTheOthersPositionsStream) {
    const auto h = locus::testing::make_hierarchy(*a);
    Listener map_stream(b->port(), "/v1/maps/" + std::to_string(h.map) + "/positions/events", "");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the stream is open, with nothing to show
    ASSERT_TRUE(map_stream.seen().empty());
    const Track t = open_track(*a, {{"map_id", h.map}, {"label", "bob"}});
    post_fixes(*a, t, json::array({fix(unix_now() - 1, h.floor, 3)}));
    ASSERT_TRUE(map_stream.wait_for(1, kReach)) << "a track B never held did not appear on its positions stream";
    EXPECT_EQ(map_stream.seen()[0].first, "position");
    EXPECT_EQ(map_stream.seen()[0].second.at("track_id"), t.id);
    EXPECT_EQ(map_stream.seen()[0].second.at("fix").at("x"), 3.0);
    // Deleted on A: it leaves B's stream.
    ASSERT_EQ(track_call(*a, "DELETE", t.path(), {t.token}).status, 204);
    ASSERT_TRUE(map_stream.wait_for(2, kReach));
    EXPECT_EQ(map_stream.seen()[1].first, "leave");
    EXPECT_EQ(map_stream.seen()[1].second.at("track_id"), t.id);
}

TEST_F(ReplicaEvents, RevokingAShareOrDeletingOnOneServerEndsTheOthersStreams) {
    const auto h = locus::testing::make_hierarchy(*a);
    const Track t = open_track(*a, {{"map_id", h.map}, {"label", "cat"}});
    post_fixes(*a, t, json::array({fix(unix_now() - 5, h.floor, 1)}));
    const json share = body_of(track_call(*a, "POST", t.path("/shares"), {t.token}, "{}"), 201);
    Listener owner(b->port(), t.path("/events"), t.token);
    Listener friend_(b->port(), t.path("/events"), share.at("token").get<std::string>());
    ASSERT_TRUE(owner.wait_for(1, kReach));
    ASSERT_TRUE(friend_.wait_for(1, kReach));

    ASSERT_EQ(track_call(*a, "DELETE", t.path("/shares/" + std::to_string(share.at("id").get<std::int64_t>())), {t.token}).status, 204);
    EXPECT_TRUE(friend_.ended(1.0)) << "the share revoked on A kept its stream on B open";
    post_fixes(*a, t, json::array({fix(unix_now() - 4, h.floor, 2)}));
    ASSERT_TRUE(owner.wait_for(2, kReach));  // the owner's stream goes on
    EXPECT_EQ(fix_times(friend_.seen()).size(), 1u) << "a fix posted after the revocation reached the revoked share";

    ASSERT_EQ(track_call(*a, "DELETE", t.path(), {t.token}).status, 204);
    EXPECT_TRUE(owner.ended(1.0)) << "B's stream of a track deleted on A did not end";
    EXPECT_EQ(track_call(*b, "GET", t.path(), {t.token}).status, 404);
}

// A track fix written with no notification (as if it were lost): the change counter moves, B
// hears "everything changed" and its streams read again what they follow.
TEST_F(ReplicaEvents, AFixWhoseNotificationNeverCameIsCaughtUp) {
    Followed f(*a, *b, "dan", 30);
    ASSERT_TRUE(f.track_stream.wait_for(1, kReach));
    ASSERT_TRUE(f.map_stream.wait_for(1, kReach));
    locus::testing::database_exec(a->db(), "BEGIN; INSERT INTO track_fixes (track_id, t, floor_id, x, y, accuracy_m) VALUES (" +
                                               std::to_string(f.t.id) + ", " + std::to_string(f.t0 + 1) + ", " + std::to_string(f.h.floor) +
                                               ", 9, 1, 1.5); UPDATE change_counter SET version = version + 1; COMMIT");
    ASSERT_TRUE(f.track_stream.wait_for(2, kReach)) << "B's track stream never caught up";
    EXPECT_EQ(f.track_stream.seen()[1].second.at("x"), 9.0);
    ASSERT_TRUE(f.map_stream.wait_for(2, kReach)) << "B's positions stream never caught up";
    EXPECT_EQ(f.map_stream.seen()[1].second.at("fix").at("x"), 9.0);
}

// A lost locus_tracks notification: the servers' listener connections are ended
// (pg_terminate_backend on every backend whose last statement was the watcher's LISTEN or counter
// read) and a fix is written raw while they are down, with no NOTIFY and no counter move. Only
// B's reconnect ("everything changed") can bring it: B's streams catch up after it.
TEST_F(ReplicaEvents, AFixWrittenWhileTheListenerWasDownIsCaughtUpAtReconnect) {
    const auto h = locus::testing::make_hierarchy(*a);
    const double t0 = unix_now() - 30;
    const Track t = open_track(*a, {{"map_id", h.map}, {"label", "hal"}});
    post_fixes(*a, t, json::array({fix(t0, h.floor, 0)}));
    Listener track_stream(b->port(), t.path("/events"), t.token);
    Listener map_stream(b->port(), "/v1/maps/" + std::to_string(h.map) + "/positions/events", "");
    ASSERT_TRUE(track_stream.wait_for(1, kReach));
    ASSERT_TRUE(map_stream.wait_for(1, kReach));
    locus::testing::database_exec(a->db(), "SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE pid <> pg_backend_pid() AND "
                                           "(query LIKE 'LISTEN %' OR query = 'SELECT version FROM change_counter WHERE id = 1')");
    locus::testing::database_exec(a->db(), "INSERT INTO track_fixes (track_id, t, floor_id, x, y, accuracy_m) VALUES (" + std::to_string(t.id) +
                                               ", " + std::to_string(t0 + 1) + ", " + std::to_string(h.floor) + ", 7, 1, 1.5)");
    ASSERT_TRUE(track_stream.wait_for(2, kReach)) << "B's track stream never caught up after its listener reconnected";
    EXPECT_EQ(track_stream.seen()[1].second.at("x"), 7.0);
    ASSERT_TRUE(map_stream.wait_for(2, kReach)) << "B's positions stream never caught up after its listener reconnected";
    EXPECT_EQ(map_stream.seen()[1].second.at("fix").at("x"), 7.0);
}

// Steps fused on A reach B's stream as A stored them, and A's filter goes on as on one server.
TEST_F(ReplicaEvents, AThinClientsStepsTrackFusesAsOnOneServer) {
    const double t0 = unix_now() - 30;
    const auto h = locus::testing::make_hierarchy(*a);
    const Track t = open_track(*a, {{"map_id", h.map}, {"label", "eve"}});
    post_fixes(*a, t, json::array({fix(t0, h.floor, 2)}));
    Listener stream(b->port(), t.path("/events"), t.token);
    ASSERT_TRUE(stream.wait_for(1, kReach));
    std::vector<json> fused;
    for (int i = 1; i <= 4; ++i) {
        const json step = {{"t", t0 + i}, {"length_m", 0.7}, {"heading_deg", 90.0}};
        const json r = body_of(track_call(*a, "POST", t.path("/steps"), {t.token}, json{{"steps", json::array({step})}}.dump()));
        ASSERT_EQ(r.at("stored"), 1);
        for (const auto& f : r.at("fused")) fused.push_back(f);
    }
    ASSERT_TRUE(stream.wait_for(1 + fused.size(), kReach));
    const auto events = stream.seen();
    for (std::size_t i = 0; i < fused.size(); ++i) {
        EXPECT_EQ(events[i + 1].second.at("t"), fused[i].at("t"));
        EXPECT_EQ(events[i + 1].second.at("x"), fused[i].at("x"));
        EXPECT_EQ(events[i + 1].second.at("y"), fused[i].at("y"));
    }

    // The same inputs on a server of its own (its own database, so the same track id and seed).
    ServerProcess single({"--quiet"});
    const auto h1 = locus::testing::make_hierarchy(single);
    const Track t1 = open_track(single, {{"map_id", h1.map}, {"label", "eve"}});
    ASSERT_EQ(t1.id, t.id);
    ASSERT_EQ(h1.floor, h.floor);
    post_fixes(single, t1, json::array({fix(t0, h1.floor, 2)}));
    std::vector<json> alone;
    for (int i = 1; i <= 4; ++i) {
        const json step = {{"t", t0 + i}, {"length_m", 0.7}, {"heading_deg", 90.0}};
        const json r = body_of(track_call(single, "POST", t1.path("/steps"), {t1.token}, json{{"steps", json::array({step})}}.dump()));
        for (const auto& f : r.at("fused")) alone.push_back(f);
    }
    EXPECT_EQ(fused, alone) << "B's streaming changed what A fused";
}

// A track closed on another server whose notification never came (a raw UPDATE: no NOTIFY, no
// counter): B's sweep, finding it quiet past its TTL but no longer live in the database, reads it
// again, so B's stream of it ends instead of staying open forever.
TEST_F(ReplicaEvents, ATrackClosedElsewhereUnnotifiedEndsAtTheSweep) {
    ServerProcess quick({"--quiet", "--track-heartbeat", "0.2", "--track-ttl", "1"}, SameDatabase{a->db()});
    const auto h = locus::testing::make_hierarchy(*a);
    const Track t = open_track(*a, {{"map_id", h.map}, {"label", "fay"}});
    post_fixes(*a, t, json::array({fix(unix_now() - 5, h.floor, 0)}));
    Listener stream(quick.port(), t.path("/events"), t.token);
    ASSERT_TRUE(stream.wait_for(1, kReach));
    locus::testing::database_exec(a->db(), "UPDATE tracks SET state = 'closed', ended_at = " + std::to_string(unix_now()) +
                                               " WHERE id = " + std::to_string(t.id));
    EXPECT_TRUE(stream.ended(3.0)) << "the stream of a track closed elsewhere, unnotified, never ended";
    EXPECT_EQ(body_of(track_call(quick, "GET", t.path(), {t.token})).at("state"), "closed");
}

// B keeps a followed track's fix count by adding what its refreshes find new: fixes posted on A
// in several requests, one a retry of a stored t, are counted once each on B however many
// refreshes (notifications, requests) read them.
TEST_F(ReplicaEvents, TheOthersFixCountFollowsRemotePostsOnceEach) {
    const auto h = locus::testing::make_hierarchy(*a);
    const double t0 = unix_now() - 60;
    const Track t = open_track(*a, {{"map_id", h.map}, {"label", "gil"}});
    post_fixes(*a, t, json::array({fix(t0, h.floor, 0)}));
    Listener stream(b->port(), t.path("/events"), t.token);
    ASSERT_TRUE(stream.wait_for(1, kReach));
    post_fixes(*a, t, json::array({fix(t0 + 1, h.floor, 1), fix(t0 + 2, h.floor, 2)}));
    EXPECT_EQ(body_of(track_call(*b, "GET", t.path(), {t.token})).at("fixes"), 3);
    post_fixes(*a, t, json::array({fix(t0 + 2, h.floor, 2), fix(t0 + 3, h.floor, 3)}));
    ASSERT_TRUE(stream.wait_for(4, kReach));
    EXPECT_EQ(fix_times(stream.seen()), (std::vector<double>{t0, t0 + 1, t0 + 2, t0 + 3}));
    EXPECT_EQ(body_of(track_call(*b, "GET", t.path(), {t.token})).at("fixes"), 4);
}

// A fault on B's tracks connection alone (the listeners stay up, so no "everything changed"):
// every other backend of the database is ended, then A stores a fix. B's refresh of it fails on
// the dead connection; it is retried (and the connection made again) rather than dropped.
TEST_F(ReplicaEvents, ARefreshThatFailsOnTheTracksConnectionIsRetried) {
    const auto h = locus::testing::make_hierarchy(*a);
    const double t0 = unix_now() - 30;
    const Track t = open_track(*a, {{"map_id", h.map}, {"label", "ida"}});
    post_fixes(*a, t, json::array({fix(t0, h.floor, 0)}));
    Listener stream(b->port(), t.path("/events"), t.token);
    ASSERT_TRUE(stream.wait_for(1, kReach));
    locus::testing::database_exec(a->db(), "SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE pid <> pg_backend_pid() AND "
                                           "datname = current_database() AND query NOT LIKE 'LISTEN %' AND "
                                           "query <> 'SELECT version FROM change_counter WHERE id = 1'");
    // A's own connections went too: its post is retried until stored.
    int status = 0;
    for (int i = 0; i < 30 && status != 200; ++i) {
        if (i > 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        status = track_call(*a, "POST", t.path("/fixes"), {t.token}, json{{"fixes", json::array({fix(t0 + 1, h.floor, 5)})}}.dump()).status;
    }
    ASSERT_EQ(status, 200);
    ASSERT_TRUE(stream.wait_for(2, kReach)) << "B dropped the fix its failed refresh was reading";
    EXPECT_EQ(stream.seen()[1].second.at("x"), 5.0);
}

}  // namespace
}  // namespace server_replica_events_test
