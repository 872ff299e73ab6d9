// The map-level positions stream (GET /v1/maps/{id}/positions/events) against the real server:
// every live track at once, each new fix within a second, a floor-followed stream seeing a
// track leave for another floor and come back, a closed track leaving, and bad input refused.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

#include "hierarchy.hpp"
#include "raw_connection.hpp"
#include "server_process.hpp"
#include "sse_listener.hpp"
#include "track_call.hpp"
#include "unix_time.hpp"

namespace server_positions_stream_test {
namespace {

using locus::testing::ServerProcess;
using locus::testing::Track;
using locus::testing::body_of;
using locus::testing::open_track;
using locus::testing::unix_now;
using nlohmann::json;

int get_status(const ServerProcess& s, const std::string& path, const std::string& api_key) {
    httplib::Client c("127.0.0.1", s.port());
    c.set_read_timeout(5, 0);
    httplib::Headers h;
    if (!api_key.empty()) h.emplace("Authorization", "Bearer " + api_key);
    const auto r = c.Get(path.c_str(), h);
    return r ? r->status : 0;
}

void post_fix(const ServerProcess& s, const Track& t, double time, std::int64_t floor, double x, double y, double accuracy = 1.5) {
    httplib::Client c("127.0.0.1", s.port());
    const json body = {{"fixes", json::array({{{"t", time}, {"floor_id", floor}, {"x", x}, {"y", y}, {"accuracy_m", accuracy}}})}};
    const auto r = c.Post(("/v1/tracks/" + std::to_string(t.id) + "/fixes").c_str(), httplib::Headers{{"X-Track-Token", t.token}},
                          body.dump(), "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
}

// A positions stream read with the API key.
struct Listener : locus::testing::SseListener {
    Listener(int port, const std::string& path, const std::string& api_key)
        : SseListener(port, path, httplib::Headers{{"Authorization", "Bearer " + api_key}}) {}
};

TEST(ServerPositionsStream, BadInputIsRefused) {
    ServerProcess s({"--quiet", "--api-key", "k1"});
    s.set_api_key("k1");
    const auto h = locus::testing::make_hierarchy(s);
    const std::string p = "/v1/maps/" + std::to_string(h.map) + "/positions/events";
    EXPECT_EQ(get_status(s, p, ""), 401);
    EXPECT_EQ(get_status(s, p, "wrong"), 401);
    EXPECT_EQ(get_status(s, "/v1/maps/999/positions/events", "k1"), 404);
    EXPECT_EQ(get_status(s, p + "?floor_id=x", "k1"), 400);
    EXPECT_EQ(get_status(s, p + "?floor_id=0", "k1"), 400);
    EXPECT_EQ(get_status(s, p + "?floor_id=-3", "k1"), 400);
}

// Status of GET `path` with extra request headers and no key.
int get_with(const ServerProcess& s, const std::string& path, const httplib::Headers& headers) {
    httplib::Client c("127.0.0.1", s.port());
    c.set_read_timeout(5, 0);
    const auto r = c.Get(path.c_str(), headers);
    return r ? r->status : 0;
}

// Everyone's positions are the operator's: the key where there is one; with none, a client on
// this machine, as the trusted proxies name it (a proxy the server was not told of makes every
// client look local, so its forwarding headers say "not local"); --public-positions: anyone.
TEST(ServerPositionsStream, PositionsAreTheOperatorsUnlessMadePublic) {
    for (const char* route : {"/positions", "/positions/events"}) {
        {
            ServerProcess s({"--quiet"});
            const auto h = locus::testing::make_hierarchy(s);
            const std::string p = "/v1/maps/" + std::to_string(h.map) + route;
            if (std::string(route) == "/positions") {
                EXPECT_EQ(get_status(s, p, ""), 200);  // (a stream answered 200 would not end)
            }
            EXPECT_EQ(get_with(s, p, {{"X-Forwarded-For", "203.0.113.7"}}), 403) << route;
            EXPECT_EQ(get_with(s, p, {{"X-Forwarded-For", "127.0.0.1"}}), 403) << route;  // no proxy named: not believed
            EXPECT_EQ(get_with(s, p, {{"Forwarded", "for=203.0.113.7"}}), 403) << route;
            EXPECT_EQ(get_with(s, p, {{"X-Real-IP", "203.0.113.7"}}), 403) << route;
        }
        {
            ServerProcess s({"--quiet", "--trusted-proxy", "127.0.0.1"});
            const auto h = locus::testing::make_hierarchy(s);
            const std::string p = "/v1/maps/" + std::to_string(h.map) + route;
            EXPECT_EQ(get_with(s, p, {{"X-Forwarded-For", "203.0.113.7"}}), 403) << route;
            EXPECT_EQ(get_with(s, p, {{"X-Forwarded-For", "127.0.0.1, 203.0.113.7"}}), 403) << route;
            if (std::string(route) == "/positions") {
                EXPECT_EQ(get_with(s, p, {{"X-Forwarded-For", "127.0.0.5"}}), 200);
            }
        }
        {
            ServerProcess s({"--quiet", "--api-key", "k1", "--public-positions"});
            s.set_api_key("k1");
            const auto h = locus::testing::make_hierarchy(s);
            const std::string p = "/v1/maps/" + std::to_string(h.map) + route;
            if (std::string(route) == "/positions") {
                EXPECT_EQ(get_with(s, p, {{"X-Forwarded-For", "203.0.113.7"}}), 200);
                EXPECT_EQ(get_status(s, p, ""), 200);
            }
            EXPECT_EQ(get_status(s, "/v1/maps/999" + std::string(route), ""), 404);
        }
    }
    // The refusal says what to do.
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    httplib::Client c("127.0.0.1", s.port());
    const auto r = c.Get(("/v1/maps/" + std::to_string(h.map) + "/positions").c_str(), {{"X-Forwarded-For", "203.0.113.7"}});
    ASSERT_TRUE(r);
    const json body = json::parse(r->body);
    EXPECT_EQ(body["error"]["code"], "forbidden");
    for (const char* flag : {"--api-key", "--trusted-proxy", "--public-positions"})
        EXPECT_NE(body["error"]["message"].get<std::string>().find(flag), std::string::npos) << flag;
}

TEST(ServerPositionsStream, AFollowedFloorSeesTracksComeMoveLeaveAndEnd) {
    ServerProcess s({"--quiet", "--track-heartbeat", "0.2"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::int64_t upper = body_of(s.post("/v1/buildings/" + std::to_string(h.building) + "/floors",
                                              {{"name", "First"}, {"level", 1}, {"width", 30.0}, {"height", 20.0}}),
                                       201)["id"];
    const double now = unix_now();
    const Track ann = open_track(s, {{"map_id", h.map}, {"label", "ann"}}),
                bob = open_track(s, {{"map_id", h.map}, {"label", "bob"}});
    post_fix(s, ann, now - 5, h.floor, 1, 1);
    post_fix(s, bob, now - 5, upper, 2, 2);
    const std::string base = "/v1/maps/" + std::to_string(h.map) + "/positions/events";
    Listener ground(s.port(), base + "?floor_id=" + std::to_string(h.floor), "");
    Listener all(s.port(), base, "");

    // At once: the tracks on the followed floor, and on the whole map.
    const auto first = ground.wait_for(1, 2.0);
    ASSERT_TRUE(first);
    EXPECT_EQ(first->first, "position");
    EXPECT_EQ(first->second["track_id"], ann.id);
    EXPECT_EQ(first->second["label"], "ann");
    ASSERT_TRUE(all.wait_for(2, 2.0));

    // A new fix within a second, with its accuracy.
    auto posted = std::chrono::steady_clock::now();
    post_fix(s, ann, now - 4, h.floor, 5, 6, 3.25);
    const auto moved = ground.wait_for(2, 1.0);
    ASSERT_TRUE(moved);
    EXPECT_LT(std::chrono::steady_clock::now() - posted, std::chrono::seconds(1));
    EXPECT_EQ(moved->first, "position");
    EXPECT_DOUBLE_EQ(moved->second["fix"]["x"].get<double>(), 5.0);
    EXPECT_DOUBLE_EQ(moved->second["fix"]["accuracy_m"].get<double>(), 3.25);

    // Ann goes upstairs: she leaves the ground floor's stream, naming where she went.
    post_fix(s, ann, now - 3, upper, 5, 6);
    const auto left = ground.wait_for(3, 1.0);
    ASSERT_TRUE(left);
    EXPECT_EQ(left->first, "leave");
    EXPECT_EQ(left->second["track_id"], ann.id);
    EXPECT_EQ(left->second["floor_id"], upper);
    // Bob moves upstairs: nothing for the ground floor.
    post_fix(s, bob, now - 3, upper, 3, 3);
    // Bob comes down: he appears.
    post_fix(s, bob, now - 2, h.floor, 4, 4);
    const auto came = ground.wait_for(4, 1.0);
    ASSERT_TRUE(came);
    EXPECT_EQ(came->first, "position");
    EXPECT_EQ(came->second["track_id"], bob.id);
    // Bob's track closes: he leaves, to no floor.
    const auto r = httplib::Client("127.0.0.1", s.port())
                       .Post(("/v1/tracks/" + std::to_string(bob.id) + "/close").c_str(), httplib::Headers{{"X-Track-Token", bob.token}}, "{}",
                             "application/json");
    ASSERT_TRUE(r);
    const auto ended = ground.wait_for(5, 1.0);
    ASSERT_TRUE(ended);
    EXPECT_EQ(ended->first, "leave");
    EXPECT_EQ(ended->second["track_id"], bob.id);
    EXPECT_TRUE(ended->second["floor_id"].is_null());

    // The whole map's stream saw every fix as a position, then Bob's end: 2 + 4 + 1.
    ASSERT_TRUE(all.wait_for(7, 1.0));
    std::this_thread::sleep_for(std::chrono::milliseconds(400));  // heartbeats only: nothing repeated
    const auto events = all.seen();
    EXPECT_EQ(events.size(), 7u);
    EXPECT_EQ(events.back().first, "leave");
    EXPECT_EQ(ground.seen().size(), 5u);
}


// A positions reader that hangs up gives its slot back at once (the stream's wait checks its
// connection four times a second), not at its next heartbeat 15 s later: with room for one
// stream, the next reader's stream opens within a few tenths of a second of the hang-up.
TEST(ServerPositionsStream, AReaderThatHungUpGivesItsSlotBackAtOnce) {
    ServerProcess s({"--quiet", "--api-key", "k1", "--max-track-streams", "1"});
    s.set_api_key("k1");
    const auto h = locus::testing::make_hierarchy(s);
    const std::string path = "/v1/maps/" + std::to_string(h.map) + "/positions/events";
    // A stream read on a raw connection: true once the server answered 200 within 0.3 s.
    const auto stream = [&](std::unique_ptr<locus::testing::RawConnection>& c) {
        c = std::make_unique<locus::testing::RawConnection>(s.port());
        if (!c->connected() || !c->send(locus::testing::raw_get(path, "Authorization: Bearer k1\r\n"))) return false;
        c->closed_within(std::chrono::milliseconds(300));
        return c->pending().starts_with("HTTP/1.1 200");
    };
    std::unique_ptr<locus::testing::RawConnection> reader, retry;
    ASSERT_TRUE(stream(reader)) << reader->pending();
    EXPECT_FALSE(stream(retry)) << "the server's one stream is taken: " << retry->pending();
    EXPECT_TRUE(retry->pending().starts_with("HTTP/1.1 503")) << retry->pending();
    reader.reset();
    const auto reopened = locus::testing::seconds_until([&] { return stream(retry); }, std::chrono::seconds(5));
    ASSERT_TRUE(reopened.has_value()) << "the slot never came back";
    EXPECT_LT(*reopened, 3.0);
}

}  // namespace
}  // namespace server_positions_stream_test
