// Per-client fair shares (docs/deploy.md "Per-client limits"): one client (one address) cannot
// hold every live track or event stream, nor spend the expensive anonymous routes for
// everyone; past its share it is told 429 with Retry-After, while a second client (from
// 127.0.0.2) is still served. The API key is exempt; X-Forwarded-For counts only from a
// --trusted-proxy. Every request here is on a new connection: the shares are by address.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "hierarchy.hpp"
#include "raw_connection.hpp"
#include "server_process.hpp"
#include "sse_listener.hpp"
#include "test_database.hpp"
#include "unix_time.hpp"
#include "build_paths.hpp"

namespace server_fair_share_test {
namespace {

using locus::testing::Response;
using locus::testing::run_command;
using locus::testing::ServerProcess;
using locus::testing::SseListener;
using nlohmann::json;

constexpr const char* kSecond = "127.0.0.2";  // a second client on the loopback network

struct Call {
    Call(std::string from = "127.0.0.1", httplib::Headers with = {}) : source(std::move(from)), headers(std::move(with)) {}
    std::string source;
    httplib::Headers headers;
};

// One request on a connection of its own from `from.source`.
Response call(const ServerProcess& s, const std::string& method, const std::string& path, const json& body = nullptr,
              const Call& from = {}) {
    httplib::Client c("127.0.0.1", s.port());
    c.set_interface(from.source);
    c.set_read_timeout(30, 0);
    if (method == "GET") return locus::testing::to_response(c.Get(path.c_str(), from.headers));
    return locus::testing::to_response(c.Post(path.c_str(), from.headers, body.is_null() ? "{}" : body.dump(), "application/json"));
}

Response open_track(const ServerProcess& s, std::int64_t map, const Call& from = {}) {
    return call(s, "POST", "/v1/tracks", {{"map_id", map}}, from);
}

// A 429 with `code`, its message naming `flag`.
void expect_limited(const Response& r, const std::string& code, const std::string& flag, const std::string& what) {
    EXPECT_EQ(r.status, 429) << what << ": " << r.raw;
    EXPECT_EQ(r.body["error"]["code"], code) << what << ": " << r.raw;
    EXPECT_NE(r.body["error"]["message"].get<std::string>().find(flag), std::string::npos) << what << ": " << r.raw;
}

long retry_after(const ServerProcess& s, const std::string& method, const std::string& path, const json& body, const Call& from) {
    httplib::Client c("127.0.0.1", s.port());
    c.set_interface(from.source);
    const auto r = method == "GET" ? c.Get(path.c_str(), from.headers)
                                   : c.Post(path.c_str(), from.headers, body.is_null() ? "{}" : body.dump(), "application/json");
    if (!r) return -1;
    const std::string v = r->get_header_value("Retry-After");
    if (v.empty() || v.find_first_not_of("0123456789") != std::string::npos) return -2;
    return std::atol(v.c_str());
}

std::string token_of(const Response& r) { return r.body.at("token").get<std::string>(); }
std::string id_of(const Response& r) { return std::to_string(r.body.at("id").get<long long>()); }
// The owner of opened track `t`, calling from `source`.
Call owner_of(const Response& t, const std::string& source = "127.0.0.1") { return {source, {{"X-Track-Token", token_of(t)}}}; }

TEST(ServerFairShare, OneClientHoldsAtMostItsLiveTracks) {
    ServerProcess s({"--quiet", "--client-live-tracks", "3", "--track-ttl", "600"});
    const auto h = locus::testing::make_hierarchy(s);
    std::vector<Response> mine;
    for (int i = 0; i < 3; ++i) {
        mine.push_back(open_track(s, h.map));
        ASSERT_EQ(mine.back().status, 201) << mine.back().raw;
    }
    const Response refused = open_track(s, h.map);
    expect_limited(refused, "too_many_live_tracks", "--client-live-tracks 3", "a fourth track");
    // Its first track closes at --track-ttl without a fix: that is when to come back.
    const long retry = retry_after(s, "POST", "/v1/tracks", {{"map_id", h.map}}, {});
    EXPECT_GE(retry, 590);
    EXPECT_LE(retry, 600);
    // Another client is not refused.
    EXPECT_EQ(open_track(s, h.map, {kSecond}).status, 201);
    // A closed track is no longer held.
    const Response closed = call(s, "POST", "/v1/tracks/" + id_of(mine[0]) + "/close", nullptr, owner_of(mine[0]));
    ASSERT_EQ(closed.status, 200) << closed.raw;
    EXPECT_EQ(open_track(s, h.map).status, 201);
    EXPECT_EQ(open_track(s, h.map).status, 429);
}

// The count is the database's (a keyed hash of the address, never the address): a restart
// forgets nothing, and replicas sharing one PostgreSQL and one API key count together.
TEST(ServerFairShare, TheLiveTrackCountOutlivesARestart) {
    ServerProcess s({"--quiet", "--api-key", "s3cret", "--client-live-tracks", "2", "--track-ttl", "600"});
    s.set_api_key("s3cret");
    const auto h = locus::testing::make_hierarchy(s);
    const Response first = open_track(s, h.map);
    ASSERT_EQ(first.status, 201) << first.raw;
    ASSERT_EQ(open_track(s, h.map).status, 201);
    s.stop();
    s.start();
    expect_limited(open_track(s, h.map), "too_many_live_tracks", "--client-live-tracks 2", "after a restart");
    EXPECT_EQ(open_track(s, h.map, {kSecond}).status, 201);
    const Response closed = call(s, "POST", "/v1/tracks/" + id_of(first) + "/close", nullptr, owner_of(first));
    ASSERT_EQ(closed.status, 200) << closed.raw;
    EXPECT_EQ(open_track(s, h.map).status, 201);
    if (s.db_path().empty()) return;  // PostgreSQL: no file to read
    // The file holds no address, only the hash, and only for live tracks.
    s.stop();
    std::ifstream in(s.db_path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(bytes.find("127.0.0.1"), std::string::npos);
    EXPECT_EQ(bytes.find("127.0.0.2"), std::string::npos);
}

TEST(ServerFairShare, ReplicasCountAClientsLiveTracksTogether) {
    if (!locus::testing::on_postgres()) GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)";
    const std::vector<std::string> args = {"--quiet", "--api-key", "s3cret", "--client-live-tracks", "3", "--track-ttl", "600"};
    ServerProcess a(args);
    a.set_api_key("s3cret");
    const auto h = locus::testing::make_hierarchy(a);
    ServerProcess b(args, locus::testing::SameDatabase{a.db()});
    ASSERT_EQ(open_track(a, h.map).status, 201);
    ASSERT_EQ(open_track(b, h.map).status, 201);
    const Response third = open_track(a, h.map);
    ASSERT_EQ(third.status, 201) << third.raw;
    expect_limited(open_track(b, h.map), "too_many_live_tracks", "--client-live-tracks 3", "a fourth, on the other replica");
    expect_limited(open_track(a, h.map), "too_many_live_tracks", "--client-live-tracks 3", "a fourth, on the first");
    EXPECT_EQ(open_track(b, h.map, {kSecond}).status, 201);
    // Closed on one replica, its slot is free on the other.
    ASSERT_EQ(call(a, "POST", "/v1/tracks/" + id_of(third) + "/close", nullptr, owner_of(third)).status, 200);
    EXPECT_EQ(open_track(b, h.map).status, 201);
}

// A server-wide cap below the per-client one is met first, with its own answer.
TEST(ServerFairShare, TheServerWideCapDecidesWhenItIsLower) {
    ServerProcess s({"--quiet", "--max-live-tracks", "2", "--client-live-tracks", "5", "--max-track-streams", "1", "--client-streams", "4",
                     "--track-heartbeat", "0.1"});
    const auto h = locus::testing::make_hierarchy(s);
    const Response t = open_track(s, h.map);
    ASSERT_EQ(t.status, 201);
    EXPECT_EQ(open_track(s, h.map).status, 201);
    const Response busy = open_track(s, h.map);
    EXPECT_EQ(busy.status, 503) << busy.raw;
    EXPECT_EQ(busy.body["error"]["code"], "server_busy");
    const json fix = {{"fixes", {{{"t", locus::testing::unix_now() - 1}, {"floor_id", h.floor}, {"x", 1.0}, {"y", 1.0}, {"accuracy_m", 2.0}}}}};
    const Call owner = owner_of(t);
    ASSERT_EQ(call(s, "POST", "/v1/tracks/" + id_of(t) + "/fixes", fix, owner).status, 200);
    SseListener first(s.port(), "/v1/maps/" + std::to_string(h.map) + "/positions/events");
    ASSERT_TRUE(first.wait_for(1, 5.0));  // its stream holds the one slot
    const Response second = call(s, "GET", "/v1/tracks/" + id_of(t) + "/events", nullptr, owner);
    EXPECT_EQ(second.status, 503) << second.raw;
    EXPECT_EQ(second.body["error"]["code"], "server_busy");
}

TEST(ServerFairShare, OneClientHoldsAtMostItsStreams) {
    ServerProcess s({"--quiet", "--track-heartbeat", "0.1", "--client-streams", "2"});
    const auto h = locus::testing::make_hierarchy(s);
    const Response t = open_track(s, h.map);
    ASSERT_EQ(t.status, 201);
    const json fix = {{"fixes", {{{"t", locus::testing::unix_now() - 1}, {"floor_id", h.floor}, {"x", 1.0}, {"y", 1.0}, {"accuracy_m", 2.0}}}}};
    ASSERT_EQ(call(s, "POST", "/v1/tracks/" + id_of(t) + "/fixes", fix, owner_of(t)).status, 200);
    const std::string events = "/v1/tracks/" + id_of(t) + "/events";
    const std::string positions = "/v1/maps/" + std::to_string(h.map) + "/positions/events";
    // One stream of each kind: both count.
    SseListener track_stream(s.port(), events, {{"X-Track-Token", token_of(t)}});
    SseListener map_stream(s.port(), positions);
    ASSERT_TRUE(track_stream.wait_for(1, 5.0));
    ASSERT_TRUE(map_stream.wait_for(1, 5.0));
    const Call owner = owner_of(t);
    expect_limited(call(s, "GET", events, nullptr, owner), "too_many_client_streams", "--client-streams 2", "a third track stream");
    expect_limited(call(s, "GET", positions), "too_many_client_streams", "--client-streams 2", "a third positions stream");
    const long retry = retry_after(s, "GET", positions, nullptr, {});
    EXPECT_GE(retry, 1);
    // Another client still gets both kinds.
    SseListener other_track(s.port(), events, {{"X-Track-Token", token_of(t)}}, kSecond);
    SseListener other_map(s.port(), positions, {}, kSecond);
    EXPECT_TRUE(other_track.wait_for(1, 5.0));
    EXPECT_TRUE(other_map.wait_for(1, 5.0));
}

// However many clients fill the server's streams, one holding fewer still opens its own: the
// oldest stream of the client holding the most (at least two more) ends as evicted to let it
// in; when every client holds about as many, the server is busy.
TEST(ServerFairShare, AFullServerLetsAClientHoldingFewerIn) {
    ServerProcess s({"--quiet", "--track-heartbeat", "0.1", "--max-track-streams", "4", "--client-streams", "3"});
    const auto h = locus::testing::make_hierarchy(s);
    const Response t = open_track(s, h.map);
    ASSERT_EQ(t.status, 201);
    const json fix = {{"fixes", {{{"t", locus::testing::unix_now() - 1}, {"floor_id", h.floor}, {"x", 1.0}, {"y", 1.0}, {"accuracy_m", 2.0}}}}};
    ASSERT_EQ(call(s, "POST", "/v1/tracks/" + id_of(t) + "/fixes", fix, owner_of(t)).status, 200);
    const std::string events = "/v1/tracks/" + id_of(t) + "/events";
    const std::string positions = "/v1/maps/" + std::to_string(h.map) + "/positions/events";
    const httplib::Headers owner{{"X-Track-Token", token_of(t)}};
    // Client A holds three, B one: the server's four.
    std::vector<std::unique_ptr<SseListener>> a;
    for (int i = 0; i < 3; ++i) {
        a.push_back(std::make_unique<SseListener>(s.port(), events, owner, "127.0.0.2"));
        ASSERT_TRUE(a.back()->wait_for(1, 5.0)) << "A's stream " << i;
    }
    SseListener b(s.port(), positions, {}, "127.0.0.3");
    ASSERT_TRUE(b.wait_for(1, 5.0));
    const auto evicted = [](SseListener& l) {
        if (!l.ended(5.0)) return false;
        const auto last = l.seen().back();
        return last.second.value("reason", "").starts_with("evicted");
    };
    // C (none) gets in; A's oldest ends.
    SseListener c(s.port(), events, owner, "127.0.0.4");
    EXPECT_TRUE(c.wait_for(1, 5.0));
    EXPECT_TRUE(evicted(*a[0]));
    EXPECT_FALSE(a[1]->ended(0.3));
    // B (one) does not take from A (two): two more are needed.
    const auto busy = call(s, "GET", positions, nullptr, {"127.0.0.3"});
    EXPECT_EQ(busy.status, 503) << busy.raw;
    EXPECT_EQ(busy.body["error"]["code"], "server_busy") << busy.raw;
    // D (none) takes A's next oldest, a positions stream as well as a track stream.
    SseListener d(s.port(), positions, {}, "127.0.0.5");
    EXPECT_TRUE(d.wait_for(1, 5.0));
    EXPECT_TRUE(evicted(*a[1]));
    EXPECT_FALSE(a[2]->ended(0.3));
    EXPECT_FALSE(b.ended(0.1));
    // Everyone holds one: a newcomer waits for a slot, and one closing frees it at once.
    EXPECT_EQ(call(s, "GET", events, nullptr, {"127.0.0.6", owner}).status, 503);
    a[2].reset();
    bool opened = false;
    for (int i = 0; i < 50 && !opened; ++i) {  // the closed stream's worker lets go at its next heartbeat
        SseListener e(s.port(), events, owner, "127.0.0.6");
        opened = e.wait_for(1, 0.5).has_value();
    }
    EXPECT_TRUE(opened);
}

TEST(ServerFairShare, TrackOpensAreRateLimited) {
    ServerProcess s({"--quiet", "--client-track-opens", "0.01", "--client-track-open-burst", "2"});
    const auto h = locus::testing::make_hierarchy(s);
    EXPECT_EQ(open_track(s, h.map).status, 201);
    EXPECT_EQ(open_track(s, h.map).status, 201);
    expect_limited(open_track(s, h.map), "rate_limited", "--client-track-opens (0.01", "a third open at once");
    // One token every 100 s.
    const long retry = retry_after(s, "POST", "/v1/tracks", {{"map_id", h.map}}, {});
    EXPECT_GE(retry, 98);
    EXPECT_LE(retry, 100);
    EXPECT_EQ(open_track(s, h.map, {kSecond}).status, 201);
}

TEST(ServerFairShare, ExpensiveRoutesShareOneRate) {
    ServerProcess s({"--quiet", "--client-rate", "0.05", "--client-burst", "3"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string map = "/v1/maps/" + std::to_string(h.map);
    const std::string search = map + "/search?q=lab";
    const json route = {{"from", {{"floor_id", h.floor}, {"x", 1.0}, {"y", 1.0}}}, {"to", {{"floor_id", h.floor}, {"x", 2.0}, {"y", 2.0}}}};
    const json scan = {{"scans", {{{{"bssid", "aa:00:00:00:00:01"}, {"rss", -50}}}}}};
    // Three of any of them, then none: each answers whatever it answers, but not 429.
    EXPECT_NE(call(s, "GET", search).status, 429);
    EXPECT_NE(call(s, "POST", map + "/route", route).status, 429);
    EXPECT_NE(call(s, "POST", map + "/localize", scan).status, 429);
    const std::string quality = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/quality";
    expect_limited(call(s, "GET", quality), "rate_limited", "--client-rate (0.05", "quality");
    expect_limited(call(s, "GET", search), "rate_limited", "--client-rate", "search");
    expect_limited(call(s, "POST", map + "/route", route), "rate_limited", "--client-rate", "route");
    expect_limited(call(s, "POST", map + "/localize", scan), "rate_limited", "--client-rate", "map localize");
    const long retry = retry_after(s, "GET", search, nullptr, {});
    EXPECT_GE(retry, 19);
    EXPECT_LE(retry, 20);
    // Other routes are not limited (the radio map's own localize, the load generator's, neither),
    // nor is another client.
    EXPECT_EQ(call(s, "GET", map).status, 200);
    EXPECT_NE(call(s, "POST", "/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize", scan).status, 429);
    EXPECT_NE(call(s, "GET", map + "/positions").status, 429);
    EXPECT_NE(call(s, "GET", search, nullptr, {kSecond}).status, 429);
    EXPECT_NE(call(s, "GET", quality, nullptr, {kSecond}).status, 429);
}

// A batch of `n` fixes one second apart from `t0`, at (x, 1).
json fixes_batch(std::int64_t floor, double t0, int n) {
    json fixes = json::array();
    for (int i = 0; i < n; ++i) fixes.push_back({{"t", t0 + i}, {"floor_id", floor}, {"x", 1.0 + 0.01 * i}, {"y", 1.0}, {"accuracy_m", 2.0}});
    return {{"fixes", fixes}};
}

TEST(ServerFairShare, WhatATrackWriterPostsIsMeteredInBytes) {
    ServerProcess s({"--quiet", "--client-track-bytes", "10", "--client-track-bytes-burst", "6000"});
    const auto h = locus::testing::make_hierarchy(s);
    const Response t = open_track(s, h.map);
    ASSERT_EQ(t.status, 201);
    const Call owner = owner_of(t);
    const std::string fixes = "/v1/tracks/" + id_of(t) + "/fixes";
    const double t0 = locus::testing::unix_now() - 1000;
    const json batch = fixes_batch(h.floor, t0, 30);
    const std::size_t bytes = batch.dump().size();
    ASSERT_GT(bytes, 1500u);
    ASSERT_LT(bytes, 3000u);  // two fit in the burst, a third does not
    EXPECT_EQ(call(s, "POST", fixes, batch, owner).status, 200);
    EXPECT_EQ(call(s, "POST", fixes, fixes_batch(h.floor, t0 + 100, 30), owner).status, 200);
    const json third = fixes_batch(h.floor, t0 + 200, 30);
    expect_limited(call(s, "POST", fixes, third, owner), "rate_limited", "--client-track-bytes (10", "a third batch at once");
    const long retry = retry_after(s, "POST", fixes, third, owner);
    EXPECT_GE(retry, 10);  // what is missing of ~2 KB at 10 bytes a second
    // The bytes are charged before the body is parsed: past the budget, even a body the route
    // would refuse as invalid (422 once parsed) is refused for its bytes, without costing the parse.
    expect_limited(call(s, "POST", fixes, json{{"fixes", std::string(bytes, 'x')}}, owner), "rate_limited", "--client-track-bytes (10",
                   "an invalid body as long as the third batch");
    // Nothing of the refused batches was stored.
    const Response info = call(s, "GET", "/v1/tracks/" + id_of(t), nullptr, owner);
    ASSERT_EQ(info.status, 200) << info.raw;
    EXPECT_EQ(info.body["fixes"], 60);
    // Another client's track posts on its own share.
    const Response other = open_track(s, h.map, {kSecond});
    ASSERT_EQ(other.status, 201);
    EXPECT_EQ(call(s, "POST", "/v1/tracks/" + id_of(other) + "/fixes", batch, owner_of(other, kSecond)).status, 200);
}

TEST(ServerFairShare, AThinClientsScansAreLocalizationsOfItsRate) {
    ServerProcess s({"--quiet", "--client-rate", "0.05", "--client-burst", "3"});
    const auto h = locus::testing::make_hierarchy(s);
    const Response t = open_track(s, h.map);
    ASSERT_EQ(t.status, 201);
    const Call owner = owner_of(t);
    const std::string steps = "/v1/tracks/" + id_of(t) + "/steps";
    const double t0 = locus::testing::unix_now() - 100;
    const auto scans = [&](int n, double from) {
        json out = json::array();
        for (int i = 0; i < n; ++i)
            out.push_back({{"t", from + i}, {"readings", {{{"bssid", "aa:00:00:00:00:01"}, {"rss", -50}}}}});
        return json{{"scans", out}};
    };
    // Five scans on a full bucket of three: admitted (whatever the fusion answers), and paid for after.
    const Response five = call(s, "POST", steps, scans(5, t0), owner);
    EXPECT_NE(five.status, 429) << five.raw;
    expect_limited(call(s, "POST", steps, scans(1, t0 + 10), owner), "rate_limited", "--client-rate (0.05", "a scan after five");
    const long retry = retry_after(s, "POST", steps, scans(1, t0 + 10), owner);
    EXPECT_GE(retry, 59);  // three tokens short at 0.05 a second
    EXPECT_LE(retry, 60);
    // The same bucket as map localize; steps without scans localize nothing and pass.
    const json scan = {{"scans", {{{{"bssid", "aa:00:00:00:00:01"}, {"rss", -50}}}}}};
    expect_limited(call(s, "POST", "/v1/maps/" + std::to_string(h.map) + "/localize", scan), "rate_limited", "--client-rate", "map localize");
    const Response fix = call(s, "POST", steps, fixes_batch(h.floor, t0 + 20, 1), owner);
    EXPECT_NE(fix.status, 429) << fix.raw;
}

TEST(ServerFairShare, TheApiKeyIsExempt) {
    ServerProcess s({"--quiet", "--api-key", "s3cret", "--client-rate", "0.01", "--client-burst", "1", "--client-live-tracks", "1",
                     "--client-track-opens", "0.01", "--client-track-open-burst", "1", "--client-streams", "1", "--track-heartbeat", "0.1"});
    s.set_api_key("s3cret");
    const auto h = locus::testing::make_hierarchy(s);
    const Call keyed{"127.0.0.1", {{"Authorization", "Bearer s3cret"}}};
    const Call wrong{"127.0.0.1", {{"Authorization", "Bearer wrong"}}};
    const std::string search = "/v1/maps/" + std::to_string(h.map) + "/search?q=lab";
    for (int i = 0; i < 5; ++i) EXPECT_EQ(call(s, "GET", search, nullptr, keyed).status, 200) << i;
    EXPECT_EQ(call(s, "GET", search).status, 200);  // the anonymous client's one
    EXPECT_EQ(call(s, "GET", search, nullptr, wrong).status, 429);
    std::vector<Response> tracks;
    for (int i = 0; i < 4; ++i) {
        tracks.push_back(open_track(s, h.map, keyed));
        EXPECT_EQ(tracks.back().status, 201) << tracks.back().raw;
    }
    EXPECT_EQ(open_track(s, h.map).status, 201);
    EXPECT_EQ(open_track(s, h.map, wrong).status, 429);
    // Positions streams need the key here; the operator's are not counted.
    const std::string positions = "/v1/maps/" + std::to_string(h.map) + "/positions/events";
    SseListener a(s.port(), positions, keyed.headers);
    SseListener b(s.port(), positions, keyed.headers);
    const Response t = tracks[0];
    SseListener mine(s.port(), "/v1/tracks/" + id_of(t) + "/events", {{"X-Track-Token", token_of(t)}});
    const json fix = {{"fixes", {{{"t", locus::testing::unix_now() - 1}, {"floor_id", h.floor}, {"x", 1.0}, {"y", 1.0}, {"accuracy_m", 2.0}}}}};
    ASSERT_EQ(call(s, "POST", "/v1/tracks/" + id_of(t) + "/fixes", fix, owner_of(t)).status, 200);
    EXPECT_TRUE(a.wait_for(1, 5.0));
    EXPECT_TRUE(b.wait_for(1, 5.0));
    EXPECT_TRUE(mine.wait_for(1, 5.0));
    // The anonymous client's one stream is taken: a second is refused.
    const Response refused = call(s, "GET", "/v1/tracks/" + id_of(t) + "/events", nullptr, owner_of(t));
    EXPECT_EQ(refused.status, 429) << refused.raw;
}

TEST(ServerFairShare, ForwardedForIsIgnoredWithoutATrustedProxy) {
    ServerProcess s({"--quiet", "--client-rate", "0.01", "--client-burst", "2"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string search = "/v1/maps/" + std::to_string(h.map) + "/search?q=lab";
    EXPECT_EQ(call(s, "GET", search, nullptr, {"127.0.0.1", {{"X-Forwarded-For", "198.51.100.1"}}}).status, 200);
    EXPECT_EQ(call(s, "GET", search, nullptr, {"127.0.0.1", {{"X-Forwarded-For", "198.51.100.2"}}}).status, 200);
    // A third address claimed in the header is still the same client.
    EXPECT_EQ(call(s, "GET", search, nullptr, {"127.0.0.1", {{"X-Forwarded-For", "198.51.100.3"}}}).status, 429);
}

TEST(ServerFairShare, ForwardedForIsHonouredFromATrustedProxy) {
    ServerProcess s({"--quiet", "--client-rate", "0.01", "--client-burst", "2", "--trusted-proxy", "10.9.9.9,127.0.0.1"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string search = "/v1/maps/" + std::to_string(h.map) + "/search?q=lab";
    const Call one{"127.0.0.1", {{"X-Forwarded-For", "198.51.100.1"}}};
    // The client wrote a left entry of its own: the proxy's (right-most) entry decides.
    const Call one_spoofing{"127.0.0.1", {{"X-Forwarded-For", "203.0.113.50, 198.51.100.1"}}};
    const Call two{"127.0.0.1", {{"X-Forwarded-For", "198.51.100.2"}}};
    EXPECT_EQ(call(s, "GET", search, nullptr, one).status, 200);
    EXPECT_EQ(call(s, "GET", search, nullptr, one_spoofing).status, 200);
    EXPECT_EQ(call(s, "GET", search, nullptr, one).status, 429);
    EXPECT_EQ(call(s, "GET", search, nullptr, two).status, 200);
    // 127.0.0.2 is no trusted proxy: its header counts for nothing, it is one client of its own.
    const Call untrusted{kSecond, {{"X-Forwarded-For", "198.51.100.7"}}};
    EXPECT_EQ(call(s, "GET", search, nullptr, untrusted).status, 200);
    EXPECT_EQ(call(s, "GET", search, nullptr, {kSecond, {{"X-Forwarded-For", "198.51.100.8"}}}).status, 200);
    EXPECT_EQ(call(s, "GET", search, nullptr, {kSecond, {{"X-Forwarded-For", "198.51.100.9"}}}).status, 429);
    // ...while the address it named is still a fresh client behind the proxy.
    EXPECT_EQ(call(s, "GET", search, nullptr, {"127.0.0.1", {{"X-Forwarded-For", "198.51.100.7"}}}).status, 200);
}

TEST(ServerFairShare, BadFlagValuesAreRefusedAtStart) {
    const struct {
        std::vector<std::string> args;
        std::string said;
    } cases[] = {
        {{"--trusted-proxy", "nginx"}, "'nginx' is not an IP address or CIDR range"},
        {{"--trusted-proxy", "10.0.0.1,10.0.0.0/33"}, "'10.0.0.0/33'"},
        {{"--client-rate", "0"}, "--client-rate"},
        {{"--client-burst", "0.5"}, "--client-burst"},
        {{"--client-live-tracks", "0"}, "--client-live-tracks"},
        {{"--client-streams", "-1"}, "--client-streams"},
        {{"--client-track-opens", "fast"}, "--client-track-opens"},
        {{"--client-track-open-burst", "0"}, "--client-track-open-burst"},
        {{"--client-track-bytes", "0"}, "--client-track-bytes"},
        {{"--client-track-bytes-burst", "0.5"}, "--client-track-bytes-burst"},
    };
    const std::string dir = locus::testing::make_temp_dir();
    for (const auto& c : cases) {
        // Bounded in time: a value taken by mistake would start a server that never stops.
        std::vector<std::string> argv = {"/usr/bin/timeout", "10", LOCUS_SERVER_BIN, "--db", dir + "/never.db", "--port", "0", "--quiet"};
        argv.insert(argv.end(), c.args.begin(), c.args.end());
        const auto r = run_command(argv);
        EXPECT_NE(r.status, 0) << c.args[0] << " " << c.args[1];
        EXPECT_NE((r.err + r.out).find(c.said), std::string::npos) << c.args[0] << " " << c.args[1] << ": " << r.err << r.out;
        EXPECT_EQ((r.err + r.out).find("\"listening\""), std::string::npos) << "it started: " << r.err;
    }
    std::filesystem::remove_all(dir);
}

// A client that waits for 100 Continue is charged once, and refused before it sends its body.
TEST(ServerFairShare, AClientWaitingForContinueIsChargedOnceAndRefusedFirst) {
    ServerProcess s({"--quiet", "--client-track-opens", "0.01", "--client-track-open-burst", "2"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string body = json{{"map_id", h.map}}.dump();
    const std::string head = "POST /v1/tracks HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: " +
                             std::to_string(body.size()) + "\r\nExpect: 100-continue\r\n\r\n";
    for (int i = 0; i < 2; ++i) {
        locus::testing::RawConnection c(s.port());
        ASSERT_TRUE(c.send(head));
        const auto go = c.read_answer();
        ASSERT_TRUE(go.has_value());
        EXPECT_EQ(go->status, 100) << "open " << i;
        ASSERT_TRUE(c.send(body));
        const auto opened = c.read_answer();
        ASSERT_TRUE(opened.has_value());
        EXPECT_EQ(opened->status, 201) << "open " << i << " (charged twice?): " << opened->body;
    }
    locus::testing::RawConnection c(s.port());
    ASSERT_TRUE(c.send(head));
    const auto refused = c.read_answer();
    ASSERT_TRUE(refused.has_value());
    EXPECT_EQ(refused->status, 429) << "the third is refused before its body: " << refused->body;
}

}  // namespace
}  // namespace server_fair_share_test
