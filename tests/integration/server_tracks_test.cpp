// Live tracks over HTTP against the real server: fixes in any order and twice, the trail, a
// share that opens one track only, every bad input refused with nothing written, an event
// stream that sees a posted fix within a second, the relative position of two tracks against
// hand-computed values, and tracks closing and going with tiny --track-ttl/--track-retention.
// Eigen first: cpp-httplib pulls in <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include "locus/motion/fusion/particle_filter.hpp"
#include "locus/motion/fusion/walk_filter.hpp"

#include <httplib.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <numbers>
#include <thread>

#include "hierarchy.hpp"
#include "locus/api/client.hpp"
#include "locus/plan/geojson.hpp"
#include "plan_geojson.hpp"
#include "raw_connection.hpp"
#include "server_process.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_tracks_test {
namespace {

using locus::testing::Response;
using locus::testing::ServerProcess;
using locus::testing::Track;
using locus::testing::body_of;
using locus::testing::open_track;
using locus::testing::track_call;
using locus::testing::with_api_key;
using locus::testing::unix_now;
using nlohmann::json;

json fix(double t, std::int64_t floor, double x, double y, std::optional<double> heading = std::nullopt) {
    json f = {{"t", t}, {"floor_id", floor}, {"x", x}, {"y", y}, {"accuracy_m", 1.5}};
    if (heading) f["heading_deg"] = *heading;
    return f;
}

Response post_fixes(const ServerProcess& s, const Track& t, const std::vector<json>& fixes, const std::string& token = "") {
    json body = json::object();
    body["fixes"] = json(fixes);
    return track_call(s, "POST", "/v1/tracks/" + std::to_string(t.id) + "/fixes", {token.empty() ? t.token : token}, body.dump());
}

std::string path_of(const Track& t, const std::string& rest = "") { return "/v1/tracks/" + std::to_string(t.id) + rest; }

TEST(ServerTracks, FixesInAnyOrderAndTwiceMakeOneOrderedTrail) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}});
    const double t0 = unix_now() - 10;
    json first = body_of(post_fixes(s, t, {fix(t0 + 2, h.floor, 2, 0), fix(t0, h.floor, 0, 0), fix(t0 + 1, h.floor, 1, 0, 90.0)}));
    EXPECT_EQ(first["stored"], 3);
    EXPECT_EQ(first["duplicates"], 0);
    // A retry of t0 + 1 with other values, and an older fix arriving late.
    json second = body_of(post_fixes(s, t, {fix(t0 + 1, h.floor, 9, 9), fix(t0 - 1, h.floor, -1, 0)}));
    EXPECT_EQ(second["stored"], 1);
    EXPECT_EQ(second["duplicates"], 1);
    const json got = body_of(track_call(s, "GET", path_of(t), {t.token}));
    EXPECT_EQ(got["state"], "live");
    EXPECT_EQ(got["fixes"], 4);
    EXPECT_DOUBLE_EQ(got["latest"]["x"].get<double>(), 2.0);  // the largest t, not the last posted
    ASSERT_EQ(got["trail"].size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(got["trail"][i]["x"].get<double>(), static_cast<double>(i) - 1.0);
    EXPECT_DOUBLE_EQ(got["trail"][2]["heading_deg"].get<double>(), 90.0);  // the first of t0 + 1 kept
    const json two = body_of(track_call(s, "GET", path_of(t, "?limit=2"), {t.token}));
    ASSERT_EQ(two["trail"].size(), 2u);
    EXPECT_DOUBLE_EQ(two["trail"][1]["x"].get<double>(), 2.0);
}

TEST(ServerTracks, AShareReadsOneTrackUntilRevoked) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track a = open_track(s, {{"map_id", h.map}, {"label", "ann"}}),
                b = open_track(s, {{"map_id", h.map}, {"label", "bob"}});
    body_of(post_fixes(s, a, {fix(unix_now(), h.floor, 1, 1)}));
    const json share = body_of(track_call(s, "POST", path_of(a, "/shares"), {a.token}, "{}"), 201);
    const std::string st = share["token"];
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(a), {st}))["label"], "ann");
    EXPECT_EQ(track_call(s, "GET", path_of(b), {st}).status, 403);  // one track only
    EXPECT_EQ(post_fixes(s, a, {fix(unix_now(), h.floor, 2, 2)}, st).status, 403);  // reads, never writes
    EXPECT_EQ(track_call(s, "POST", path_of(a, "/shares"), {st}, "{}").status, 403);
    EXPECT_EQ(track_call(s, "DELETE", path_of(a), {st}).status, 403);
    EXPECT_EQ(track_call(s, "DELETE", path_of(a, "/shares/" + std::to_string(share["id"].get<std::int64_t>())), {a.token}).status, 204);
    EXPECT_EQ(track_call(s, "GET", path_of(a), {st}).status, 403);
    EXPECT_EQ(track_call(s, "DELETE", path_of(a, "/shares/" + std::to_string(share["id"].get<std::int64_t>())), {a.token}).status, 404);
}

TEST(ServerTracks, BadInputIsRefusedAndWritesNothing) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const auto other = locus::testing::make_hierarchy(s, "Elsewhere");
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}});
    const double now = unix_now();
    auto code = [](const Response& r) { return r.body.is_object() ? r.body["error"]["code"].get<std::string>() : std::string("?"); };

    EXPECT_EQ(track_call(s, "POST", "/v1/tracks", {}, R"({"map_id": 999})").status, 422);
    EXPECT_EQ(track_call(s, "POST", "/v1/tracks", {}, R"({"map_id": "1"})").status, 422);
    EXPECT_EQ(track_call(s, "POST", "/v1/tracks", {}, R"({"map_id": 1, "colour": "red"})").status, 422);

    const Response missing = track_call(s, "POST", path_of(t, "/fixes"), {}, R"({"fixes": [{"t": 1, "floor_id": 1, "x": 0, "y": 0, "accuracy_m": 1}]})");
    EXPECT_EQ(missing.status, 401);
    EXPECT_EQ(code(missing), "unauthorized");
    const Response wrong = post_fixes(s, t, {fix(now, h.floor, 0, 0)}, "trk_0000");
    EXPECT_EQ(wrong.status, 403);
    // An unknown track answers as a wrong token does: a token tells nothing of other tracks.
    const Response unknown = post_fixes(s, Track{t.id + 100, t.token}, {fix(now, h.floor, 0, 0)});
    EXPECT_EQ(unknown.status, 403);
    EXPECT_EQ(code(unknown), code(wrong));
    EXPECT_EQ(track_call(s, "GET", "/v1/tracks/999", {t.token}).status, 403);

    const std::string p = path_of(t, "/fixes");
    EXPECT_EQ(track_call(s, "POST", p, {t.token}, R"({"fixes": [{"t": NaN, "floor_id": 1, "x": 0, "y": 0, "accuracy_m": 1}]})").status, 400);
    EXPECT_EQ(post_fixes(s, t, {fix(now, h.floor, 1e308 * 10, 0)}).status, 422);  // infinity is written as null: not a number
    EXPECT_EQ(code(post_fixes(s, t, {fix(now, h.floor, 1e9, 0)})), "out_of_range");
    EXPECT_EQ(code(post_fixes(s, t, {fix(now, other.floor, 0, 0)})), "invalid_field");  // a floor of another map
    EXPECT_EQ(code(post_fixes(s, t, {fix(now, 987654, 0, 0)})), "invalid_field");
    EXPECT_EQ(code(post_fixes(s, t, {fix(now + 3600, h.floor, 0, 0)})), "invalid_field");  // far in the future
    EXPECT_EQ(code(post_fixes(s, t, {fix(now, h.floor, 0, 0), json{{"t", now}}})), "invalid_field");
    EXPECT_EQ(code(post_fixes(s, t, {})), "invalid_field");
    std::vector<json> many;
    for (int i = 0; i < 1001; ++i) many.push_back(fix(now - 100 + i * 0.01, h.floor, 0, 0));
    const Response big = post_fixes(s, t, many);
    EXPECT_EQ(big.status, 413);
    EXPECT_EQ(code(big), "batch_too_large");
    // A good fix before a bad one in the same batch: neither is written.
    EXPECT_EQ(post_fixes(s, t, {fix(now, h.floor, 0, 0), fix(now + 1, h.floor, 0, std::nan(""))}).status, 422);
    EXPECT_EQ(post_fixes(s, t, {fix(now, h.floor, 0, 0), fix(now + 1, other.floor, 0, 0)}).status, 422);
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(t), {t.token}))["fixes"], 0);  // every refused batch wrote nothing

    // A floor of the map that is deleted is no longer one to post on.
    const auto extra = body_of(s.post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                                      {{"name", "Annex"}, {"level", 3}, {"width", 10.0}, {"height", 10.0}}), 201)["id"].get<std::int64_t>();
    EXPECT_EQ(post_fixes(s, t, {fix(now - 1, extra, 0, 0)}).status, 200);
    EXPECT_EQ(s.del("/v1/floors/" + std::to_string(extra)).status, 204);
    EXPECT_EQ(code(post_fixes(s, t, {fix(now, extra, 0, 0)})), "invalid_field");

    // Closed: no more fixes, no new shares; closing twice is fine.
    EXPECT_EQ(body_of(track_call(s, "POST", path_of(t, "/close"), {t.token}, "{}"))["state"], "closed");
    EXPECT_EQ(track_call(s, "POST", path_of(t, "/close"), {t.token}, "{}").status, 200);
    EXPECT_EQ(code(post_fixes(s, t, {fix(now, h.floor, 0, 0)})), "track_closed");
    EXPECT_EQ(code(track_call(s, "POST", path_of(t, "/shares"), {t.token}, "{}")), "track_closed");
    EXPECT_EQ(track_call(s, "GET", path_of(t, "?limit=5000"), {t.token}).status, 400);

    // Deleted: the owner is told it went, anyone else learns nothing.
    EXPECT_EQ(track_call(s, "DELETE", path_of(t), {t.token}).status, 204);
    EXPECT_EQ(track_call(s, "GET", path_of(t), {t.token}).status, 404);
    EXPECT_EQ(track_call(s, "GET", path_of(t), {"trk_guess"}).status, 403);
}

TEST(ServerTracks, RelativePositionMatchesHandComputedValues) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track a = open_track(s, {{"map_id", h.map}, {"label", "ann"}}),
                b = open_track(s, {{"map_id", h.map}, {"label", "bob"}});
    const double now = unix_now();
    const std::string rel = "/v1/tracks/" + std::to_string(a.id) + "/relative/" + std::to_string(b.id);
    body_of(post_fixes(s, a, {fix(now - 2, h.floor, 1, 1, 90.0)}));  // facing +x
    EXPECT_EQ(track_call(s, "GET", rel, {a.token, b.token}).status, 409);  // b has no fix yet
    body_of(post_fixes(s, b, {fix(now - 1, h.floor, 4, 5)}));
    EXPECT_EQ(track_call(s, "GET", rel, {a.token}).status, 401);
    const std::string b_share = body_of(track_call(s, "POST", path_of(b, "/shares"), {b.token}, "{}"), 201)["token"];
    const json r = body_of(track_call(s, "GET", rel, {a.token, b_share}));
    EXPECT_NEAR(r["straight_distance_m"].get<double>(), 5.0, 1e-9);
    // b is 3 m along +x and 4 m along +y: bearing atan2(3, 4) = 36.87° clockwise from +y,
    // 53.13° left of a's heading of 90°.
    EXPECT_NEAR(r["bearing_deg"].get<double>(), 36.8699, 1e-3);
    EXPECT_NEAR(r["relative_bearing_deg"].get<double>(), -53.1301, 1e-3);
    EXPECT_EQ(r["direction"], "ahead, 53\u00b0 left");
    EXPECT_EQ(r["floor_difference"], 0);
    EXPECT_NEAR(r["from"]["age_s"].get<double>(), 2.0, 1.0);
    EXPECT_NEAR(r["to"]["age_s"].get<double>(), 1.0, 1.0);
    EXPECT_FALSE(r.contains("walking_distance_m"));  // the floor has no plan to walk on
    EXPECT_TRUE(r.contains("walking_problem"));
    // a's token for b's side, or b's share for a's side, does not do.
    EXPECT_EQ(track_call(s, "GET", rel, {b_share, a.token}).status, 403);
    EXPECT_EQ(track_call(s, "GET", rel, {a.token, "shr_nothing"}).status, 403);
}

TEST(ServerTracks, PositionsNeedTheApiKeyAndListLiveTracks) {
    ServerProcess s({"--quiet", "--api-key", "k1"});
    s.set_api_key("k1");
    const auto h = locus::testing::make_hierarchy(s);
    s.set_api_key("");
    const Track a = open_track(s, {{"map_id", h.map}, {"label", "ann"}}),
                b = open_track(s, {{"map_id", h.map}, {"label", "bob"}});
    open_track(s, {{"map_id", h.map}, {"label", "no fix yet"}});
    body_of(post_fixes(s, a, {fix(unix_now(), h.floor, 1, 1)}));
    body_of(post_fixes(s, b, {fix(unix_now(), h.floor, 2, 2)}));
    const std::string p = "/v1/maps/" + std::to_string(h.map) + "/positions";
    EXPECT_EQ(track_call(s, "GET", p).status, 401);
    EXPECT_EQ(track_call(s, "GET", p, with_api_key("wrong")).status, 401);
    EXPECT_EQ(track_call(s, "GET", p, {a.token}).status, 401);  // a track's token is not the operator's key
    const json all = body_of(track_call(s, "GET", p, with_api_key("k1")));
    ASSERT_EQ(all["positions"].size(), 2u);
    EXPECT_EQ(all["positions"][0]["label"], "ann");
    EXPECT_EQ(all["positions"][1]["fix"]["x"], 2.0);
    EXPECT_EQ(body_of(track_call(s, "GET", p + "?floor_id=" + std::to_string(h.floor + 1000), with_api_key("k1")))["positions"].size(), 0u);
    EXPECT_EQ(track_call(s, "GET", p + "?floor_id=x", with_api_key("k1")).status, 400);
    EXPECT_EQ(track_call(s, "GET", "/v1/maps/999/positions", with_api_key("k1")).status, 404);
    body_of(track_call(s, "POST", path_of(a, "/close"), {a.token}, "{}"));
    EXPECT_EQ(body_of(track_call(s, "GET", p, with_api_key("k1")))["positions"].size(), 1u);
}

// Reads an event stream on its own thread, keeping every `data:` line.
struct Listener {
    std::mutex mu;
    std::vector<json> fixes;
    std::atomic<bool> ended{false}, stop{false};
    int status = 0;
    std::thread thread;

    Listener(int port, const std::string& path, const std::string& token) {
        thread = std::thread([this, port, path, token] {
            httplib::Client c("127.0.0.1", port);
            c.set_read_timeout(10, 0);
            std::string buf;
            auto r = c.Get(path.c_str(), httplib::Headers{{"X-Track-Token", token}}, [&](const char* data, std::size_t n) {
                buf.append(data, n);
                for (std::size_t end; (end = buf.find("\n\n")) != std::string::npos; buf.erase(0, end + 2)) {
                    const std::string event = buf.substr(0, end);
                    if (event.starts_with("event: end")) ended = true;
                    if (const auto d = event.find("data: "); event.starts_with("event: fix") && d != std::string::npos) {
                        std::lock_guard lock(mu);
                        fixes.push_back(json::parse(event.substr(d + 6)));
                    }
                }
                return !stop.load();
            });
            if (r) status = r->status;
        });
    }
    ~Listener() {
        stop = true;
        thread.join();
    }
    std::size_t count() {
        std::lock_guard lock(mu);
        return fixes.size();
    }
    bool wait_for(std::size_t n, double seconds) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (count() < n && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        return count() >= n;
    }
};

TEST(ServerTracks, AnEventStreamSeesEachFixWithinASecond) {
    ServerProcess s({"--quiet", "--track-heartbeat", "0.2", "--max-track-streams", "2"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}});
    const double now = unix_now();
    body_of(post_fixes(s, t, {fix(now - 5, h.floor, 0, 0)}));
    const std::string share = body_of(track_call(s, "POST", path_of(t, "/shares"), {t.token}, "{}"), 201)["token"];
    Listener owner(s.port(), path_of(t, "/events"), t.token);
    Listener friend_(s.port(), path_of(t, "/events"), share);
    ASSERT_TRUE(owner.wait_for(1, 2.0));  // the latest fix, at once
    ASSERT_TRUE(friend_.wait_for(1, 2.0));
    // A third stream is past --max-track-streams; a wrong token never gets one.
    EXPECT_EQ(track_call(s, "GET", path_of(t, "/events"), {t.token}).status, 503);
    EXPECT_EQ(track_call(s, "GET", path_of(t, "/events"), {"trk_wrong"}).status, 403);

    for (int i = 0; i < 3; ++i) {
        const auto posted = std::chrono::steady_clock::now();
        body_of(post_fixes(s, t, {fix(now + i, h.floor, i + 1.0, 0)}));
        ASSERT_TRUE(owner.wait_for(2 + i, 1.0)) << "fix " << i;
        ASSERT_TRUE(friend_.wait_for(2 + i, 1.0)) << "fix " << i;
        EXPECT_LT(std::chrono::steady_clock::now() - posted, std::chrono::seconds(1));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // heartbeats only: no fix repeated
    EXPECT_EQ(owner.count(), 4u);
    EXPECT_DOUBLE_EQ(owner.fixes.back()["x"].get<double>(), 3.0);
    // Closing ends both streams.
    body_of(track_call(s, "POST", path_of(t, "/close"), {t.token}, "{}"));
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (!(owner.ended && friend_.ended) && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_TRUE(owner.ended);
    EXPECT_TRUE(friend_.ended);
}

// One track's owner and shares could take every event stream slot of the server.
TEST(ServerTracks, OneTrackCannotTakeEveryStreamSlot) {
    ServerProcess s({"--quiet", "--track-heartbeat", "0.1", "--max-streams-per-track", "2", "--max-track-streams", "10"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track a = open_track(s, {{"map_id", h.map}, {"label", "ann"}}),
                b = open_track(s, {{"map_id", h.map}, {"label", "bob"}});
    body_of(post_fixes(s, a, {fix(unix_now() - 1, h.floor, 0, 0)}));
    body_of(post_fixes(s, b, {fix(unix_now() - 1, h.floor, 1, 0)}));
    const std::string share = body_of(track_call(s, "POST", path_of(a, "/shares"), {a.token}, "{}"), 201)["token"];
    auto first = std::make_unique<Listener>(s.port(), path_of(a, "/events"), a.token);
    Listener second(s.port(), path_of(a, "/events"), share);
    ASSERT_TRUE(first->wait_for(1, 2.0));
    ASSERT_TRUE(second.wait_for(1, 2.0));
    const Response refused = track_call(s, "GET", path_of(a, "/events"), {a.token});
    EXPECT_EQ(refused.status, 429);
    EXPECT_EQ(refused.body["error"]["code"], "too_many_streams") << refused.raw;
    Listener other(s.port(), path_of(b, "/events"), b.token);  // another track still gets one
    EXPECT_TRUE(other.wait_for(1, 2.0));
    // A closed stream gives its slot back.
    first.reset();
    bool again = false;
    for (int i = 0; i < 20 && !again; ++i) {
        Listener retry(s.port(), path_of(a, "/events"), a.token);
        again = retry.wait_for(1, 0.3);
    }
    EXPECT_TRUE(again);
}

// A reader that hangs up gives its stream's slot back at once: the stream's wait looks at its
// connection four times a second, rather than learning of the hang-up from its next heartbeat's
// failed write 15 s (the default heartbeat) later.
TEST(ServerTracks, AStreamWhoseReaderHungUpGivesItsSlotBackAtOnce) {
    ServerProcess s({"--quiet", "--max-streams-per-track", "1"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track a = open_track(s, {{"map_id", h.map}, {"label", "ann"}});
    body_of(post_fixes(s, a, {fix(unix_now() - 1, h.floor, 0, 0)}));
    // A stream read on a raw connection: true once its first fix came within 0.3 s.
    const auto stream = [&](std::unique_ptr<locus::testing::RawConnection>& c) {
        c = std::make_unique<locus::testing::RawConnection>(s.port());
        if (!c->connected() || !c->send(locus::testing::raw_get(path_of(a, "/events"), "X-Track-Token: " + a.token + "\r\n"))) return false;
        c->closed_within(std::chrono::milliseconds(300));
        return c->pending().find("event: fix") != std::string::npos;
    };
    std::unique_ptr<locus::testing::RawConnection> reader, retry;
    ASSERT_TRUE(stream(reader)) << reader->pending();
    EXPECT_FALSE(stream(retry)) << "the track's one slot is taken: " << retry->pending();
    EXPECT_NE(retry->pending().find(" 429 "), std::string::npos) << retry->pending();
    reader.reset();
    const auto reopened = locus::testing::seconds_until([&] { return stream(retry); }, std::chrono::seconds(5));
    ASSERT_TRUE(reopened.has_value()) << "the slot never came back";
    EXPECT_LT(*reopened, 3.0);
}

// An anonymous loop of open and close (or delete) had no bound, so every track held is capped
// (--max-tracks); but a loop of opens and deletes then filled the cap with tombstones and
// refused everyone's opens for up to a day. Tombstones, then closed tracks, now give way to a
// new track, oldest first: only live tracks fill the cap. The retention here is a day, so
// nothing expires on its own during the test.
TEST(ServerTracks, OnlyLiveTracksFillTheTrackCap) {
    ServerProcess s({"--quiet", "--max-tracks", "3", "--track-ttl", "600"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track live = open_track(s, {{"map_id", h.map}, {"label", "live"}});
    const Track closed = open_track(s, {{"map_id", h.map}, {"label", "closed"}});
    body_of(post_fixes(s, closed, {fix(unix_now() - 1, h.floor, 1, 1)}));
    body_of(track_call(s, "POST", path_of(closed, "/close"), {closed.token}, "{}"));
    std::vector<Track> deleted;
    for (int i = 0; i < 10; ++i) {  // well past the cap
        deleted.push_back(open_track(s, {{"map_id", h.map}, {"label", "loop"}}));
        ASSERT_EQ(track_call(s, "DELETE", path_of(deleted.back()), {deleted.back().token}).status, 204) << i;
    }
    // Each open evicted the oldest tombstone: the latest one still answers its owner 404, an
    // evicted one 403 as for a track never opened; the closed track kept its fixes.
    EXPECT_EQ(track_call(s, "GET", path_of(deleted.back()), {deleted.back().token}).status, 404);
    EXPECT_EQ(track_call(s, "GET", path_of(deleted.front()), {deleted.front().token}).status, 403);
    const json kept = body_of(track_call(s, "GET", path_of(closed), {closed.token}));
    EXPECT_EQ(kept["state"], "closed");
    EXPECT_EQ(kept["trail"].size(), 1u) << kept.dump();

    // With no tombstone left, the closed track gives way.
    const Track second = open_track(s, {{"map_id", h.map}, {"label", "second"}});
    EXPECT_EQ(track_call(s, "GET", path_of(closed), {closed.token}).status, 200);  // the last tombstone went first
    const Track third = open_track(s, {{"map_id", h.map}, {"label", "third"}});
    EXPECT_EQ(track_call(s, "GET", path_of(closed), {closed.token}).status, 403);

    // Live tracks alone fill it: an honest 503, and nothing given way.
    const Response refused = track_call(s, "POST", "/v1/tracks", {}, json{{"map_id", h.map}}.dump());
    EXPECT_EQ(refused.status, 503);
    EXPECT_EQ(refused.body["error"]["code"], "too_many_tracks") << refused.raw;
    for (const Track& t : {live, second, third}) EXPECT_EQ(body_of(track_call(s, "GET", path_of(t), {t.token}))["state"], "live");
    // A live track closing frees its slot for the next open.
    body_of(track_call(s, "POST", path_of(third, "/close"), {third.token}, "{}"));
    EXPECT_EQ(track_call(s, "POST", "/v1/tracks", {}, json{{"map_id", h.map}}.dump()).status, 201);
}

// Two servers on one PostgreSQL database: a track evicted at --max-tracks by one, or gone
// with its map deleted there, answers on the other as on the first (Replication::refresh finds
// its row gone and tells the two apart by whether the map is still there): 403 for the
// evicted one, as for a track never opened, and 404 for the one whose map went.
TEST(ServerTracks, AnotherServerAnswersAnEvictedTrack403AndOneWhoseMapWent404) {
    if (!locus::testing::on_postgres()) GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)";
    ServerProcess a({"--quiet", "--max-tracks", "3", "--track-ttl", "600"});
    ServerProcess b({"--quiet", "--track-ttl", "600"}, locus::testing::SameDatabase{a.db()});
    const auto h = locus::testing::make_hierarchy(a);
    const auto other = locus::testing::make_hierarchy(a, "Elsewhere");

    // Both servers hold both tracks in memory before anything happens to them.
    const Track on_other_map = open_track(a, {{"map_id", other.map}, {"label", "elsewhere"}});
    const Track closed = open_track(a, {{"map_id", h.map}, {"label", "closed"}});
    body_of(post_fixes(a, closed, {fix(unix_now() - 1, h.floor, 1, 1)}));
    body_of(track_call(a, "POST", path_of(closed, "/close"), {closed.token}, "{}"));
    EXPECT_EQ(body_of(track_call(b, "GET", path_of(closed), {closed.token}))["state"], "closed");
    EXPECT_EQ(body_of(track_call(b, "GET", path_of(on_other_map), {on_other_map.token}))["state"], "live");

    // At a's cap (3) the next open evicts the one closed track.
    const Track live = open_track(a, {{"map_id", h.map}, {"label", "live"}});
    const Track evicting = open_track(a, {{"map_id", h.map}, {"label", "evicting"}});
    EXPECT_EQ(track_call(a, "GET", path_of(closed), {closed.token}).status, 403);
    for (int i = 0; i < 2; ++i) {  // the second time from b's memory, the row being gone
        const Response r = track_call(b, "GET", path_of(closed), {closed.token});
        EXPECT_EQ(r.status, 403) << i << ": " << r.raw;
        EXPECT_EQ(r.body["error"]["code"], "forbidden") << r.raw;
    }
    for (const Track& t : {live, evicting}) EXPECT_EQ(body_of(track_call(b, "GET", path_of(t), {t.token}))["state"], "live");

    // Its map deleted on a: gone on both, 404 to its owner rather than 403.
    ASSERT_EQ(a.del("/v1/maps/" + std::to_string(other.map)).status, 204);
    for (int i = 0; i < 2; ++i) {
        const Response r = track_call(b, "GET", path_of(on_other_map), {on_other_map.token});
        EXPECT_EQ(r.status, 404) << i << ": " << r.raw;
    }
    EXPECT_EQ(track_call(a, "GET", path_of(on_other_map), {on_other_map.token}).status, 404);
}

// Deleting a map deleted its tracks' rows, but in memory they lived on (a post answered 409
// or worse, a stream stayed open): now they go with it.
TEST(ServerTracks, DeletingAMapEndsItsTracks) {
    ServerProcess s({"--quiet", "--track-heartbeat", "0.1"});
    const auto h = locus::testing::make_hierarchy(s);
    const auto other = locus::testing::make_hierarchy(s, "Elsewhere");
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}}),
                kept = open_track(s, {{"map_id", other.map}, {"label", "phone"}});
    body_of(post_fixes(s, t, {fix(unix_now() - 1, h.floor, 1, 1)}));
    const std::string share = body_of(track_call(s, "POST", path_of(t, "/shares"), {t.token}, "{}"), 201)["token"];
    Listener stream(s.port(), path_of(t, "/events"), t.token);
    ASSERT_TRUE(stream.wait_for(1, 2.0));

    ASSERT_EQ(s.del("/v1/maps/" + std::to_string(h.map)).status, 204);
    EXPECT_EQ(track_call(s, "GET", path_of(t), {t.token}).status, 404);
    EXPECT_EQ(post_fixes(s, t, {fix(unix_now(), h.floor, 2, 2)}).status, 404);
    EXPECT_EQ(track_call(s, "POST", path_of(t, "/close"), {t.token}, "{}").status, 404);
    EXPECT_EQ(track_call(s, "GET", path_of(t), {share}).status, 403);
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (!stream.ended && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_TRUE(stream.ended);
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(kept), {kept.token}))["state"], "live");  // another map's track is untouched
}

// A revoked share had kept an open stream receiving every fix for as long as the track lived.
TEST(ServerTracks, RevokingAShareEndsTheStreamsItOpened) {
    ServerProcess s({"--quiet", "--track-heartbeat", "0.2"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}});
    const double now = unix_now();
    body_of(post_fixes(s, t, {fix(now - 5, h.floor, 0, 0)}));
    const json share = body_of(track_call(s, "POST", path_of(t, "/shares"), {t.token}, "{}"), 201);
    Listener owner(s.port(), path_of(t, "/events"), t.token);
    Listener friend_(s.port(), path_of(t, "/events"), share["token"].get<std::string>());
    ASSERT_TRUE(owner.wait_for(1, 2.0));
    ASSERT_TRUE(friend_.wait_for(1, 2.0));

    EXPECT_EQ(track_call(s, "DELETE", path_of(t, "/shares/" + std::to_string(share["id"].get<std::int64_t>())), {t.token}).status, 204);
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (!friend_.ended && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_TRUE(friend_.ended) << "the revoked share's stream stayed open";
    body_of(post_fixes(s, t, {fix(now, h.floor, 7, 0)}));
    ASSERT_TRUE(owner.wait_for(2, 1.0));  // the owner's stream goes on
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_EQ(friend_.count(), 1u) << "a fix posted after the revocation reached the revoked share";
    EXPECT_FALSE(owner.ended);
}

TEST(ServerTracks, ATrackClosesAfterItsTtlAndGoesAfterRetention) {
    ServerProcess s({"--quiet", "--track-ttl", "0.4", "--track-retention", "1.5"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}});
    body_of(post_fixes(s, t, {fix(unix_now(), h.floor, 1, 1)}));
    const std::string share = body_of(track_call(s, "POST", path_of(t, "/shares"), {t.token}, "{}"), 201)["token"];
    std::string state;
    for (int i = 0; i < 100 && state != "closed"; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        state = body_of(track_call(s, "GET", path_of(t), {t.token}))["state"];
    }
    EXPECT_EQ(state, "closed");
    EXPECT_EQ(post_fixes(s, t, {fix(unix_now(), h.floor, 1, 1)}).status, 409);
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(t), {share}))["state"], "closed");  // still readable until retention
    int status = 200;
    for (int i = 0; i < 100 && status == 200; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        status = track_call(s, "GET", path_of(t), {t.token}).status;
    }
    EXPECT_EQ(status, 404);  // expired: the owner is told, the share opens nothing
    EXPECT_EQ(track_call(s, "GET", path_of(t), {share}).status, 403);
    // Nothing of it is left in the database but its tombstone, and a restart keeps it so.
    s.stop();
    s.start();
    EXPECT_EQ(track_call(s, "GET", path_of(t), {t.token}).status, 404);
}

// A live track keeps its last retention period of fixes; its count had kept every fix ever
// posted, so a track posting for days was refused as full.
TEST(ServerTracks, ALongLiveTrackCountsOnlyTheFixesItKeeps) {
    ServerProcess s({"--quiet", "--track-ttl", "60", "--track-retention", "1"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}});
    const double start = unix_now();
    body_of(post_fixes(s, t, {fix(start - 0.2, h.floor, 1, 1), fix(start - 0.1, h.floor, 2, 1)}));
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(t), {t.token}))["fixes"], 2);
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));  // both older than the retention period
    body_of(post_fixes(s, t, {fix(unix_now(), h.floor, 3, 1)}));
    int fixes = -1;
    for (int i = 0; i < 100 && fixes != 1; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        fixes = body_of(track_call(s, "GET", path_of(t), {t.token}))["fixes"].get<int>();
    }
    EXPECT_EQ(fixes, 1);
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(t), {t.token}))["trail"].size(), 1u);
}

// A thin client's steps and radio fixes, fused on the server, give exactly what client-lib's
// filter gives on the same inputs here: one code path. The older particle filter, chosen per
// track, gives client-lib's ParticleFilter's fixes.
TEST(ServerTracks, ServerFusionGivesClientLibsFixes) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    using locus::testing::feature;
    const json plan = {{"type", "FeatureCollection"},
                       {"features", {feature("space", locus::testing::rect_polygon(0, 0, 20, 4), {{"name", "Corridor"}, {"kind", "corridor"}}),
                                     feature("space", locus::testing::rect_polygon(0, 4, 8, 10), {{"name", "Lab"}}),
                                     feature("wall", locus::testing::line({{0, 4}, {8, 4}}))}}};
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(h.floor) + "/plan", plan).status, 200);
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}, {"fusion", "particle"}});
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(t), {t.token}))["fusion"], "particle");
    const double t0 = std::floor(unix_now()) - 30;
    const std::string p = path_of(t, "/steps");
    // Steps with nowhere to start from are refused, and nothing is stored.
    json steps_only = {{"steps", {{{"t", t0}, {"length_m", 0.7}, {"heading_deg", 90}}}}};
    const Response refused = track_call(s, "POST", p, {t.token}, steps_only.dump());
    EXPECT_EQ(refused.status, 422);
    EXPECT_EQ(refused.body["error"]["code"], "cannot_fuse");

    json steps = json::array();
    for (int i = 1; i <= 6; ++i) steps.push_back({{"t", t0 + i}, {"length_m", 0.7}, {"heading_deg", 90.0}});
    const json body = {{"steps", steps},
                       {"fixes", {{{"t", t0}, {"floor_id", h.floor}, {"x", 2.0}, {"y", 2.0}, {"accuracy_m", 2.0}},
                                  {{"t", t0 + 3}, {"floor_id", h.floor}, {"x", 4.5}, {"y", 2.5}, {"accuracy_m", 1.5}}}}};
    const json got = body_of(track_call(s, "POST", p, {t.token}, body.dump()));
    ASSERT_EQ(got["fused"].size(), 8u);
    EXPECT_EQ(got["stored"], 7);  // the radio fix and the step at t0 + 3: the track keeps the state after both

    // The same in client-lib, on the plan as the server keeps it.
    json stored = body_of(s.get("/v1/floors/" + std::to_string(h.floor) + "/plan"));
    const auto walkable = locus::fusion::Walkable::from_plan(locus::plan::from_geojson({{"type", "FeatureCollection"}, {"features", stored["features"]}}));
    locus::fusion::ParticleConfig config;
    config.seed = static_cast<std::uint64_t>(t.id);  // the server seeds a track's filter with its id
    locus::fusion::ParticleFilter pf(walkable, {2.0, 2.0}, config);
    std::vector<locus::Point> expected{pf.position()};
    auto step = [&] {
        pf.predict(0.7, 90.0 * std::numbers::pi / 180.0);
        expected.push_back(pf.position());
    };
    step(), step();
    pf.update({4.5, 2.5}, Eigen::Matrix2d::Identity() * 1.5 * 1.5);  // the radio fix at t0 + 3 comes before the step at t0 + 3
    expected.push_back(pf.position());
    step(), step(), step(), step();
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_NEAR(got["fused"][i]["x"].get<double>(), expected[i].x, 1e-9) << i;
        EXPECT_NEAR(got["fused"][i]["y"].get<double>(), expected[i].y, 1e-9) << i;
    }
    EXPECT_GT(got["fused"][7]["x"].get<double>(), 5.0);  // it walked east
    // The next request goes on from where this one left the filter.
    const json more = body_of(track_call(s, "POST", p, {t.token}, json{{"steps", {{{"t", t0 + 7}, {"length_m", 0.7}, {"heading_deg", 90.0}}}}}.dump()));
    pf.predict(0.7, 90.0 * std::numbers::pi / 180.0);
    EXPECT_NEAR(more["fused"][0]["x"].get<double>(), pf.position().x, 1e-9);
    EXPECT_DOUBLE_EQ(body_of(track_call(s, "GET", path_of(t), {t.token}))["latest"]["x"].get<double>(), more["fused"][0]["x"].get<double>());
    // Bad steps: a step longer than 3 m, a floor of no plan, a share token.
    EXPECT_EQ(track_call(s, "POST", p, {t.token}, json{{"steps", {{{"t", t0 + 8}, {"length_m", 9}, {"heading_deg", 0}}}}}.dump()).status, 422);
    EXPECT_EQ(track_call(s, "POST", p, {t.token}, R"({"steps": []})").status, 422);
    EXPECT_EQ(track_call(s, "POST", p, {t.token}, R"({"walk": []})").status, 422);
}

// A thin client's scans are localized as the map's localize endpoint answers them (the same
// index, the radio map's default algorithm) and taken by the particle filter as its radio fixes:
// the fused fixes are client-lib's on those fixes. A bad scan anywhere in a batch writes nothing
// and leaves the filter where it was.
TEST(ServerTracks, ServerFusionLocalizesScansLikeTheLocalizeEndpoint) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    using locus::testing::feature;
    const json plan = {{"type", "FeatureCollection"},
                       {"features", {feature("space", locus::testing::rect_polygon(0, 0, 20, 4), {{"name", "Corridor"}, {"kind", "corridor"}})}}};
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(h.floor) + "/plan", plan).status, 200);
    const auto m = [](const std::string& bssid, double mean) {
        return json{{"type", "wifi"}, {"bssid", bssid}, {"mean", mean}, {"variance", 4.0}, {"count", 10}};
    };
    json rps = json::array();
    for (int i = 0; i < 5; ++i) {
        const double x = 2.0 + 4.0 * i;
        rps.push_back({{"name", "rp" + std::to_string(i)}, {"x", x}, {"y", 2.0}, {"scans", 10},
                       {"measurements", {m("aa:00:00:00:00:01", -35 - 2.0 * x), m("aa:00:00:00:00:02", -75 + 2.0 * x)}}});
    }
    ASSERT_EQ(s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", json{{"name", "corridor"}, {"rps", rps}}).status, 201);
    const auto readings = [](double ap1, double ap2) {
        return json::array({{{"bssid", "AA:00:00:00:00:01"}, {"rss", ap1}}, {{"type", "wifi"}, {"bssid", "aa:00:00:00:00:02"}, {"rss", ap2}}});
    };
    const json west = readings(-40, -72), middle = readings(-55, -57);
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}});
    const double t0 = std::floor(unix_now()) - 30;
    const std::string p = path_of(t, "/steps");

    // Bad scans, alone or beside good steps: 4xx, nothing stored.
    const json good_steps = {{{"t", t0 + 1}, {"length_m", 0.7}, {"heading_deg", 90.0}}};
    for (const json& bad : {json{{"t", t0}, {"readings", json::array()}},
                            json{{"t", t0}, {"readings", {{{"bssid", "not-a-mac"}, {"rss", -50}}}}},
                            json{{"t", t0}, {"readings", {{{"bssid", "aa:00:00:00:00:01"}, {"rss", 20}}}}},
                            json{{"t", t0}, {"readings", {{{"bssid", "aa:00:00:00:00:01"}, {"rss", "strong"}}}}},
                            json{{"t", t0}, {"readings", {{{"bssid", "bb:00:00:00:00:09"}, {"rss", -50}}}}},  // no RP hears it
                            json{{"t", t0}, {"readings", west}, {"floor_id", h.floor}},
                            json{{"t", unix_now() + 3600}, {"readings", west}},
                            json{{"readings", west}},
                            json(west)}) {
        const Response r = track_call(s, "POST", p, {t.token}, json{{"steps", good_steps}, {"scans", {bad}}}.dump());
        EXPECT_EQ(r.status, 422) << bad.dump() << " " << r.raw;
        EXPECT_TRUE(r.body["error"].contains("code")) << r.raw;
    }
    EXPECT_EQ(track_call(s, "POST", p, {t.token}, json{{"scans", json::object()}}.dump()).status, 422);
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(t), {t.token}))["fixes"], 0);

    // The first scan starts the filter, steps walk it east, the second scan corrects it.
    json steps = json::array();
    for (int i = 1; i <= 8; ++i) steps.push_back({{"t", t0 + i}, {"length_m", 0.7}, {"heading_deg", 90.0}});
    const json body = {{"steps", steps}, {"scans", {{{"t", t0 + 4.5}, {"readings", middle}}, {{"t", t0}, {"readings", west}}}}};
    const json got = body_of(track_call(s, "POST", p, {t.token}, body.dump()));
    ASSERT_EQ(got["fused"].size(), 10u);
    EXPECT_EQ(got["stored"], 10);
    ASSERT_EQ(got["scan_fixes"].size(), 2u);

    // Each scan's fix is where the map's localize endpoint puts that scan.
    const std::string localize = "/v1/maps/" + std::to_string(h.map) + "/localize";
    std::vector<json> answers;
    for (const json* r : {&west, &middle}) answers.push_back(body_of(s.post(localize, json{{"scans", json::array({*r})}})));
    for (std::size_t i = 0; i < 2; ++i) {
        const json& f = got["scan_fixes"][i];
        EXPECT_DOUBLE_EQ(f["x"].get<double>(), answers[i]["x"].get<double>()) << i;
        EXPECT_DOUBLE_EQ(f["y"].get<double>(), answers[i]["y"].get<double>()) << i;
        EXPECT_EQ(f["floor_id"], h.floor);
        EXPECT_GE(f["accuracy_m"].get<double>(), 1.0);  // never the centimetres of a lone candidate
    }
    EXPECT_LT(answers[0]["x"].get<double>(), 6.0);   // the west scan is west...
    EXPECT_GT(answers[1]["x"].get<double>(), 6.0);   // ...the middle one further east

    // The same in client-lib, on the plan as the server keeps it and the fixes the scans gave.
    const json stored = body_of(s.get("/v1/floors/" + std::to_string(h.floor) + "/plan"));
    const auto walkable = locus::fusion::Walkable::from_plan(locus::plan::from_geojson({{"type", "FeatureCollection"}, {"features", stored["features"]}}));
    const json& f0 = got["scan_fixes"][0];
    const json& f1 = got["scan_fixes"][1];
    auto config = locus::fusion::WalkFilterConfig::real_walks();
    config.seed = static_cast<std::uint64_t>(t.id);
    locus::fusion::WalkFilter pf(walkable, config);
    const double a0 = f0["accuracy_m"].get<double>();
    pf.fix({f0["x"].get<double>(), f0["y"].get<double>()}, Eigen::Matrix2d::Identity() * a0 * a0);
    std::vector<locus::Point> expected{pf.position()};
    for (int i = 1; i <= 8; ++i) {
        pf.step(0.7, 90.0 * std::numbers::pi / 180.0);
        expected.push_back(pf.position());
        if (i == 4) {
            const double a = f1["accuracy_m"].get<double>();
            pf.fix({f1["x"].get<double>(), f1["y"].get<double>()}, Eigen::Matrix2d::Identity() * a * a);
            expected.push_back(pf.position());
        }
    }
    ASSERT_EQ(expected.size(), 10u);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_NEAR(got["fused"][i]["x"].get<double>(), expected[i].x, 1e-9) << i;
        EXPECT_NEAR(got["fused"][i]["y"].get<double>(), expected[i].y, 1e-9) << i;
    }
    // A bad scan after that leaves the filter where it was: the next good step is client-lib's next step.
    EXPECT_EQ(track_call(s, "POST", p, {t.token}, json{{"steps", {{{"t", t0 + 9}, {"length_m", 0.7}, {"heading_deg", 90.0}}}},
                                                  {"scans", {{{"t", t0 + 9}, {"readings", {{{"bssid", "bb:00:00:00:00:09"}, {"rss", -50}}}}}}}}.dump())
                  .status,
              422);
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(t), {t.token}))["fixes"], 10);
    const json next = body_of(track_call(s, "POST", p, {t.token}, json{{"steps", {{{"t", t0 + 9}, {"length_m", 0.7}, {"heading_deg", 90.0}}}}}.dump()));
    pf.step(0.7, 90.0 * std::numbers::pi / 180.0);
    EXPECT_NEAR(next["fused"][0]["x"].get<double>(), pf.position().x, 1e-9);
}

// A track fuses with walk_pf (client-lib's WalkFilter, real-walk preset, seeded with the track's
// id) unless it asks otherwise, and walk_pf needs no plan: a floor without one fuses, each fused
// fix client-lib's position with the cloud's spread as its accuracy. Steps before any fix are
// still refused; the particle filter on a floor without a plan is refused with nothing stored.
TEST(ServerTracks, ServerFusionRunsWalkFilterByDefaultWithOrWithoutAPlan) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);  // its floor has no plan
    // A track first, so this one's id, its seed, is not the default seed 1.
    (void)open_track(s, {{"map_id", h.map}, {"label", "first"}});
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}});
    ASSERT_NE(t.id, 1);
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(t), {t.token}))["fusion"], "walk_pf");
    const double t0 = std::floor(unix_now()) - 30;
    const std::string p = path_of(t, "/steps");
    const Response refused = track_call(s, "POST", p, {t.token}, json{{"steps", {{{"t", t0}, {"length_m", 0.7}, {"heading_deg", 90}}}}}.dump());
    EXPECT_EQ(refused.status, 422);
    EXPECT_EQ(refused.body["error"]["code"], "cannot_fuse");

    // Radio fixes walking east with steps whose compass is turned by 90°: walk_pf learns that.
    json steps = json::array(), fixes = json::array();
    for (int i = 1; i <= 12; ++i) steps.push_back({{"t", t0 + i}, {"length_m", 0.7}, {"heading_deg", 0.0}});
    for (int i = 0; i <= 12; i += 3) fixes.push_back({{"t", t0 + i}, {"floor_id", h.floor}, {"x", 2.0 + 0.7 * i}, {"y", 2.0}, {"accuracy_m", i == 0 ? 2.0 : 0.3}});
    const json got = body_of(track_call(s, "POST", p, {t.token}, json{{"steps", steps}, {"fixes", fixes}}.dump()));
    ASSERT_EQ(got["fused"].size(), 17u);
    EXPECT_EQ(got["stored"], 13);  // a fix and a step at one t: the track keeps the state after both

    auto config = locus::fusion::WalkFilterConfig::real_walks();
    config.seed = static_cast<std::uint64_t>(t.id);
    // The server's order: a fix before the step of equal t.
    locus::fusion::WalkFilter wf(std::nullopt, config);
    std::vector<std::pair<locus::Point, double>> ordered;
    for (int i = 0; i <= 12; ++i) {
        if (i % 3 == 0) {
            const double a = std::max(i == 0 ? 2.0 : 0.3, 0.5);  // the server's floor on a fix's claimed accuracy
            wf.fix({2.0 + 0.7 * i, 2.0}, Eigen::Matrix2d::Identity() * a * a);
            ordered.emplace_back(wf.position(), wf.spread());
        }
        if (i > 0) {
            wf.step(0.7, 0.0);
            ordered.emplace_back(wf.position(), wf.spread());
        }
    }
    ASSERT_EQ(ordered.size(), 17u);
    for (std::size_t i = 0; i < ordered.size(); ++i) {
        const json& f = got["fused"][i];
        EXPECT_NEAR(f["x"].get<double>(), ordered[i].first.x, 1e-9) << i;
        EXPECT_NEAR(f["y"].get<double>(), ordered[i].first.y, 1e-9) << i;
        EXPECT_NEAR(f["accuracy_m"].get<double>(), ordered[i].second, 1e-9) << i;
        EXPECT_EQ(f["floor_id"], h.floor);
    }
    EXPECT_GT(ordered.back().second, 0.0);
    // A retry of that request (its answer lost) moves the filter no further and stores nothing.
    const json retried = body_of(track_call(s, "POST", p, {t.token}, json{{"steps", steps}, {"fixes", fixes}}.dump()));
    EXPECT_EQ(retried["fused"].size(), 0u);
    EXPECT_EQ(retried["stored"], 0);
    // The next request goes on from where the first left the filter.
    const json more = body_of(track_call(s, "POST", p, {t.token}, json{{"steps", {{{"t", t0 + 13}, {"length_m", 0.7}, {"heading_deg", 0.0}}}}}.dump()));
    wf.step(0.7, 0.0);
    EXPECT_NEAR(more["fused"][0]["x"].get<double>(), wf.position().x, 1e-9);
    EXPECT_NEAR(more["fused"][0]["y"].get<double>(), wf.position().y, 1e-9);

    // A fix on another floor starts the filter again there, on that floor's plan, same seed.
    using locus::testing::feature;
    const std::int64_t upstairs = body_of(s.post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                                                 {{"name", "First"}, {"level", 1}, {"width", 30.0}, {"height", 20.0}}),
                                          201)["id"];
    const json plan = {{"type", "FeatureCollection"},
                       {"features", {feature("space", locus::testing::rect_polygon(0, 0, 20, 4), {{"name", "Corridor"}, {"kind", "corridor"}}),
                                     feature("wall", locus::testing::line({{0, 4}, {20, 4}}))}}};
    ASSERT_EQ(s.put("/v1/floors/" + std::to_string(upstairs) + "/plan", plan).status, 200);
    const json moved = body_of(track_call(s, "POST", p, {t.token},
                                    json{{"fixes", {{{"t", t0 + 14}, {"floor_id", upstairs}, {"x", 3.0}, {"y", 2.0}, {"accuracy_m", 1.0}}}},
                                         {"steps", {{{"t", t0 + 15}, {"length_m", 0.7}, {"heading_deg", 0.0}}}}}
                                        .dump()));
    ASSERT_EQ(moved["fused"].size(), 2u);
    const json stored = body_of(s.get("/v1/floors/" + std::to_string(upstairs) + "/plan"));
    locus::fusion::WalkFilter up(locus::fusion::Walkable::from_plan(locus::plan::from_geojson({{"type", "FeatureCollection"}, {"features", stored["features"]}})),
                                 config);
    up.fix({3.0, 2.0}, Eigen::Matrix2d::Identity());
    EXPECT_NEAR(moved["fused"][0]["x"].get<double>(), up.position().x, 1e-9);
    up.step(0.7, 0.0);
    EXPECT_NEAR(moved["fused"][1]["x"].get<double>(), up.position().x, 1e-9);
    EXPECT_NEAR(moved["fused"][1]["y"].get<double>(), up.position().y, 1e-9);
    EXPECT_NEAR(moved["fused"][1]["accuracy_m"].get<double>(), up.spread(), 1e-9);
    EXPECT_EQ(moved["fused"][1]["floor_id"], upstairs);

    // The particle filter walks on a plan: on this floor it refuses, and stores nothing.
    const Track old = open_track(s, {{"map_id", h.map}, {"label", "old"}, {"fusion", "particle"}});
    const Response no_plan = track_call(s, "POST", path_of(old, "/steps"), {old.token},
                                  json{{"steps", steps}, {"fixes", fixes}}.dump());
    EXPECT_EQ(no_plan.status, 422) << no_plan.raw;
    EXPECT_EQ(no_plan.body["error"]["code"], "cannot_fuse");
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(old), {old.token}))["fixes"], 0);
}

// A track whose filter the server does not hold (here after a restart; on PostgreSQL also when
// another server fused its last steps) starts again at its latest stored fix instead of
// refusing the steps: the same fixes as client-lib's WalkFilter started there.
TEST(ServerTracks, AFilterTheServerDoesNotHoldResumesAtTheLatestStoredFix) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);  // no plan: walk_pf walks freely
    const Track t = open_track(s, {{"map_id", h.map}, {"label", "phone"}});
    const double t0 = std::floor(unix_now()) - 30;
    const std::string p = path_of(t, "/steps");
    const json first = {{"fixes", {{{"t", t0}, {"floor_id", h.floor}, {"x", 4.0}, {"y", 3.0}, {"accuracy_m", 1.5}}}},
                        {"steps", {{{"t", t0 + 1}, {"length_m", 0.7}, {"heading_deg", 0.0}}}}};
    ASSERT_EQ(track_call(s, "POST", p, {t.token}, first.dump()).status, 200);
    s.stop();
    s.start();
    const json latest = body_of(track_call(s, "GET", path_of(t), {t.token}))["latest"];
    ASSERT_EQ(latest["t"], t0 + 1);
    const json resumed = body_of(track_call(s, "POST", p, {t.token},
                                      json{{"steps", {{{"t", t0 + 1}, {"length_m", 0.7}, {"heading_deg", 0.0}},  // already run
                                                      {{"t", t0 + 2}, {"length_m", 0.7}, {"heading_deg", 0.0}}}}}
                                          .dump()));
    ASSERT_EQ(resumed["fused"].size(), 1u) << resumed.dump();
    auto config = locus::fusion::WalkFilterConfig::real_walks();
    config.seed = static_cast<std::uint64_t>(t.id);
    locus::fusion::WalkFilter wf(std::nullopt, config);
    const double a = std::max(latest["accuracy_m"].get<double>(), 0.5);
    wf.fix({latest["x"].get<double>(), latest["y"].get<double>()}, Eigen::Matrix2d::Identity() * a * a);
    wf.step(0.7, 0.0);
    EXPECT_NEAR(resumed["fused"][0]["x"].get<double>(), wf.position().x, 1e-9);
    EXPECT_NEAR(resumed["fused"][0]["y"].get<double>(), wf.position().y, 1e-9);
    EXPECT_EQ(resumed["fused"][0]["floor_id"], h.floor);
}

// `fusion` names one of the two filters; anything else is refused and opens no track.
TEST(ServerTracks, OpeningATrackRefusesAnUnknownFusion) {
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const Track first = open_track(s, {{"map_id", h.map}, {"label", "a"}, {"fusion", "walk_pf"}});
    for (const json& bad : {json("kalman"), json("WALK_PF"), json(""), json(1), json(nullptr), json::array({"walk_pf"})}) {
        const Response r = track_call(s, "POST", "/v1/tracks", {}, json{{"map_id", h.map}, {"fusion", bad}}.dump());
        EXPECT_EQ(r.status, 422) << bad.dump() << " " << r.raw;
        EXPECT_EQ(r.body["error"]["code"], "invalid_field") << r.raw;
        EXPECT_NE(r.body["error"]["message"].get<std::string>().find("fusion"), std::string::npos) << r.raw;
    }
    // Nothing was written: the next track takes the next id.
    const json next = body_of(track_call(s, "POST", "/v1/tracks", {}, json{{"map_id", h.map}, {"fusion", "particle"}}.dump()), 201);
    EXPECT_EQ(next["id"].get<std::int64_t>(), first.id + 1);
    EXPECT_EQ(next["fusion"], "particle");
    // The choice is stored with the track: a restart keeps it.
    s.stop();
    s.start();
    const Track reopened{next["id"].get<std::int64_t>(), next["token"].get<std::string>()};
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(reopened), {reopened.token}))["fusion"], "particle");
    EXPECT_EQ(body_of(track_call(s, "GET", path_of(first), {first.token}))["fusion"], "walk_pf");
}

// The REST client's track calls against the real server.
TEST(ServerTracks, ClientTrackCalls) {
    ServerProcess s({"--quiet", "--api-key", "k2"});
    s.set_api_key("k2");
    const auto h = locus::testing::make_hierarchy(s);
    locus::api::ClientOptions phone_options;
    phone_options.base_url = s.url();
    locus::api::Client phone(phone_options);  // no API key: a phone
    auto operator_options = phone_options;
    operator_options.api_key = "k2";
    locus::api::Client op(operator_options);

    const auto ann = phone.open_track(h.map, "ann"), bob = phone.open_track(h.map, "bob");
    EXPECT_DOUBLE_EQ(ann.ttl_s, 600.0);
    const double now = unix_now();
    const auto posted = phone.post_fixes(ann.key, {{now - 1, h.floor, 1, 1, 1, 0.0}, {now - 2, h.floor, 0, 1, 1, std::nullopt}});
    EXPECT_EQ(posted.stored, 2);
    EXPECT_EQ(phone.post_fixes(ann.key, {{now - 1, h.floor, 9, 9, 1, std::nullopt}}).duplicates, 1);
    phone.post_fixes(bob.key, {{now - 1, h.floor, 1, 4, 1, std::nullopt}});
    const auto state = phone.track(ann.key);
    EXPECT_EQ(state.state, "live");
    ASSERT_EQ(state.trail.size(), 2u);
    EXPECT_DOUBLE_EQ(state.trail[0].x, 0.0);
    ASSERT_TRUE(state.latest && state.latest->heading_deg);
    const auto share = phone.share_track(bob.key);
    const json rel = phone.relative(ann.key, share.key);
    EXPECT_NEAR(rel["straight_distance_m"].get<double>(), 3.0, 1e-9);
    EXPECT_EQ(rel["direction"], "ahead");  // ann faces +y (0°), bob is 3 m along +y
    EXPECT_EQ(op.positions(h.map).size(), 2u);
    EXPECT_THROW(phone.positions(h.map), locus::api::ApiError);  // the operator's view needs the key
    phone.revoke_share(bob.key, share.id);
    EXPECT_THROW(phone.track(share.key), locus::api::ApiError);
    phone.close_track(ann.key);
    EXPECT_EQ(phone.track(ann.key).state, "closed");
    phone.delete_track(ann.key);
    try {
        phone.track(ann.key);
        ADD_FAILURE() << "a deleted track was read";
    } catch (const locus::api::ApiError& e) {
        EXPECT_EQ(e.status(), 404);
    }
}

}  // namespace
}  // namespace server_tracks_test
