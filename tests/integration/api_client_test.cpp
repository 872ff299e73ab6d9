// The REST client (locus/api/client.hpp) against the real server, and its retry policy
// against small in-process servers that fail on purpose or start late.
#include <gtest/gtest.h>
#include <httplib.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "locus/api/client.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace api_client_test {
namespace {

using namespace locus;
using locus::testing::ServerProcess;
using nlohmann::json;
using namespace std::chrono_literals;

api::ClientOptions fast_retries(const std::string& url, int attempts = 8) {
    api::ClientOptions o;
    o.base_url = url;
    o.retry.max_attempts = attempts;
    o.retry.initial_backoff = 20ms;
    o.retry.max_backoff = 200ms;
    o.connect_timeout = 500ms;
    o.read_timeout = 5000ms;
    return o;
}

// A port nothing listens on right now: bind a plain socket to port 0, read it, close it.
int free_port() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = 0;
    socklen_t len = sizeof addr;
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
        throw std::runtime_error("cannot find a free port");
    close(fd);
    return ntohs(addr.sin_port);
}

struct Chain {
    api::MapInfo map;
    api::BuildingInfo building;
    api::FloorInfo floor;
    api::RadioMapInfo radiomap;
};

Chain make_chain(api::Client& c) {
    Chain ch;
    ch.map = c.ensure_map("HQ");
    ch.building = c.ensure_building(ch.map.id, "Main");
    api::FloorInfo f;
    f.building_id = ch.building.id;
    f.name = "Ground";
    f.width = 20;
    f.height = 10;
    ch.floor = c.ensure_floor(f);
    ch.radiomap = c.ensure_radiomap(ch.floor.id, "wifi");
    return ch;
}

TEST(RetryPolicy, DoublesUpToTheCapAndHonoursJitter) {
    api::RetryPolicy p;
    p.initial_backoff = 100ms;
    p.max_backoff = 1000ms;
    EXPECT_EQ(api::backoff_delay(p, 1), 100ms);
    EXPECT_EQ(api::backoff_delay(p, 2), 200ms);
    EXPECT_EQ(api::backoff_delay(p, 4), 800ms);
    EXPECT_EQ(api::backoff_delay(p, 5), 1000ms);
    EXPECT_EQ(api::backoff_delay(p, 30), 1000ms);
    EXPECT_EQ(api::backoff_delay(p, 2, 0.5), 100ms);
    EXPECT_EQ(api::backoff_delay(p, 2, 0.1), 100ms);  // jitter clamped to [0.5, 1]
}

TEST(RetryPolicy, RetriesOnlyWhatCanSucceedLater) {
    EXPECT_TRUE(api::is_retryable(0));
    EXPECT_TRUE(api::is_retryable(429));
    EXPECT_TRUE(api::is_retryable(500));
    EXPECT_TRUE(api::is_retryable(503));
    EXPECT_FALSE(api::is_retryable(400));
    EXPECT_FALSE(api::is_retryable(401));
    EXPECT_FALSE(api::is_retryable(404));
    EXPECT_FALSE(api::is_retryable(409));
    EXPECT_FALSE(api::is_retryable(422));
}

TEST(ApiClient, HierarchyIsFoundOrCreatedOnce) {
    ServerProcess server{{"--quiet"}};
    api::Client c(fast_retries(server.url()));
    const Chain a = make_chain(c);
    const Chain b = make_chain(c);
    EXPECT_EQ(a.map.id, b.map.id);
    EXPECT_EQ(a.floor.id, b.floor.id);
    EXPECT_EQ(a.radiomap.id, b.radiomap.id);
    EXPECT_DOUBLE_EQ(b.floor.width, 20.0);
    EXPECT_EQ(c.maps().size(), 1u);
    const auto rp1 = c.ensure_rp(a.radiomap.id, "r1", 1.0, 2.0);
    EXPECT_EQ(c.ensure_rp(a.radiomap.id, "r1", 1.0, 2.0).id, rp1.id);
    EXPECT_EQ(c.retries(), 0);
}

// Rooms, POIs and RPs go to the real server from the core's types and come back as them.
TEST(ApiClient, RoomsPoisAndRpsRoundTripAsTheCoreTypes) {
    ServerProcess server{{"--quiet"}};
    api::Client c(fast_retries(server.url()));
    const Chain ch = make_chain(c);
    api::RoomInfo lab;
    lab.floor_id = ch.floor.id;
    lab.name = "lab";
    lab.rects = {{0, 0, 4, 5}, {4, 0, 6, 2}};
    const auto created = c.create_room(lab);
    EXPECT_GT(created.id, 0);
    const auto rooms = c.rooms(ch.floor.id);
    ASSERT_EQ(rooms.size(), 1u);
    EXPECT_EQ(rooms[0].floor_id, ch.floor.id);
    EXPECT_EQ(rooms[0].name, "lab");
    ASSERT_EQ(rooms[0].rects.size(), 2u);
    EXPECT_DOUBLE_EQ(rooms[0].rects[1].xmax, 6.0);
    EXPECT_TRUE(rooms[0].contains({5.0, 1.0}));

    api::PoiInfo door;
    door.floor_id = ch.floor.id;
    door.name = "door";
    door.kind = "entrance";
    door.at = {1.5, 0.5};
    EXPECT_GT(c.create_poi(door).id, 0);
    const auto pois = c.pois(ch.floor.id);
    ASSERT_EQ(pois.size(), 1u);
    EXPECT_EQ(pois[0].kind, "entrance");
    EXPECT_DOUBLE_EQ(pois[0].at.x, 1.5);
    EXPECT_DOUBLE_EQ(pois[0].at.y, 0.5);

    const auto rp = c.create_rp(ch.radiomap.id, "r", 2.0, 3.0);
    EXPECT_EQ(rp.radiomap_id, ch.radiomap.id);
    EXPECT_DOUBLE_EQ(rp.at.x, 2.0);
    EXPECT_DOUBLE_EQ(rp.at.y, 3.0);
    c.upload(rp.id, {std::nullopt, {{{"wifi", "aa:00:00:00:00:01", -50.0}}}, {}});
    const auto answer = c.localize_radiomap(ch.radiomap.id, {std::nullopt, {{{"wifi", "aa:00:00:00:00:01", -50.0}}}, {}});
    EXPECT_EQ(answer.room, "lab");
    EXPECT_EQ(answer.rp_ids, (std::vector<long long>{rp.id}));
}

TEST(ApiClient, ListsFollowEveryPage) {
    ServerProcess server{{"--quiet"}};
    api::Client c(fast_retries(server.url()));
    const Chain ch = make_chain(c);
    for (int i = 0; i < 7; ++i) c.create_rp(ch.radiomap.id, std::string("p").append(std::to_string(i)), i, 0);
    const auto rows = c.list_all("/v1/radiomaps/" + std::to_string(ch.radiomap.id) + "/rps", 3);
    ASSERT_EQ(rows.size(), 7u);
    EXPECT_EQ(rows[6]["name"], "p6");  // in creation order
}

TEST(ApiClient, ErrorsCarryTheServersCodeAndAreNotRetried) {
    ServerProcess server{{"--quiet"}};
    api::Client c(fast_retries(server.url()));
    c.create_map("dup");
    try {
        c.create_map("dup");
        FAIL() << "a duplicate name must be refused";
    } catch (const api::ApiError& e) {
        EXPECT_EQ(e.status(), 409);
        EXPECT_EQ(e.code(), "conflict");
    }
    try {
        c.rp(424242);
        FAIL() << "an unknown RP must be 404";
    } catch (const api::ApiError& e) {
        EXPECT_EQ(e.status(), 404);
        EXPECT_EQ(e.code(), "not_found");
    }
    try {
        c.post("/v1/maps", {{"name", "x"}, {"colour", "red"}});
        FAIL() << "an unknown field must be refused";
    } catch (const api::ApiError& e) {
        EXPECT_EQ(e.status(), 422);
        EXPECT_NE(std::string(e.what()).find("colour"), std::string::npos);
    }
    EXPECT_EQ(c.retries(), 0);
}

TEST(ApiClient, FloorPlansComeBackAsTheCoreType) {
    ServerProcess server{{"--quiet"}};
    api::Client c(fast_retries(server.url()));
    const Chain ch = make_chain(c);
    EXPECT_FALSE(c.plan(ch.floor.id));  // a floor without a plan

    plan::Plan p;
    const auto rect = [](double x0, double x1) { return plan::Ring{{x0, 0}, {x1, 0}, {x1, 10}, {x0, 10}, {x0, 0}}; };
    p.spaces.push_back({"West", "room", {"Ada"}, {rect(0, 10), {}}, std::nullopt});
    p.spaces.push_back({"East", "corridor", {}, {rect(10, 20), {}}, std::nullopt});
    p.walls.push_back({{{10, 0}, {10, 10}}});
    p.doors.push_back({{10, 5}, {10, 5}, "D"});
    const plan::Plan stored = c.put_plan(ch.floor.id, p);
    ASSERT_EQ(stored.spaces.size(), 2u);

    const auto got = c.plan(ch.floor.id);
    ASSERT_TRUE(got);
    ASSERT_EQ(got->spaces.size(), 2u);
    EXPECT_EQ(got->spaces[0].name, "West");
    EXPECT_EQ(got->spaces[0].tags, std::vector<std::string>{"Ada"});
    EXPECT_EQ(got->spaces[1].kind, "corridor");
    EXPECT_DOUBLE_EQ(got->spaces[1].shape.outer[1].x, 20.0);
    ASSERT_EQ(got->walls.size(), 1u);
    EXPECT_DOUBLE_EQ(got->walls[0].line[1].y, 10.0);
    ASSERT_EQ(got->doors.size(), 1u);
    EXPECT_EQ(got->doors[0].name, "D");
    EXPECT_DOUBLE_EQ(got->doors[0].a.y, 5.0);

    // An unknown floor is the server's 404, not "no plan".
    try {
        c.plan(424242);
        FAIL() << "an unknown floor must be an error";
    } catch (const api::ApiError& e) {
        EXPECT_EQ(e.status(), 404);
        EXPECT_EQ(e.code(), "not_found");
    }
    // A plan the server refuses is its 422, naming the feature; the stored plan stays.
    plan::Plan bad = p;
    bad.doors[0].a = bad.doors[0].b = {5, 5};  // in the middle of a room, on no wall
    try {
        c.put_plan(ch.floor.id, bad);
        FAIL() << "a door on no wall must be refused";
    } catch (const api::ApiError& e) {
        EXPECT_EQ(e.status(), 422);
        EXPECT_EQ(e.code(), "invalid_plan");
        EXPECT_NE(std::string(e.what()).find("doors[0]"), std::string::npos) << e.what();
    }
    EXPECT_DOUBLE_EQ(c.plan(ch.floor.id)->doors[0].a.x, 10.0);

    // Deleted, the floor has no plan again.
    c.del("/v1/floors/" + std::to_string(ch.floor.id) + "/plan");
    EXPECT_FALSE(c.plan(ch.floor.id));
    EXPECT_EQ(c.retries(), 0);
}

TEST(ApiClient, UploadIdsMakeUploadsIdempotent) {
    ServerProcess server{{"--quiet"}};
    api::Client c(fast_retries(server.url()));
    const Chain ch = make_chain(c);
    const auto rp = c.create_rp(ch.radiomap.id, "r", 5.0, 5.0);
    api::ScanUpload up;
    up.upload_id = "walk-1";
    up.scans = {{{"wifi", "aa:bb:cc:dd:ee:01", -60.0}}, {{"wifi", "aa:bb:cc:dd:ee:01", -64.0}}};
    const auto first = c.upload(rp.id, up);
    EXPECT_TRUE(first.applied);
    ASSERT_EQ(first.rp.measurements.size(), 1u);
    EXPECT_DOUBLE_EQ(first.rp.measurements[0].stats.mean, -62.0);
    EXPECT_DOUBLE_EQ(first.rp.measurements[0].stats.variance, 4.0);
    const auto second = c.upload(rp.id, up);
    EXPECT_FALSE(second.applied);
    EXPECT_EQ(second.rp.scans, 2);
    EXPECT_EQ(second.rp.measurements[0].stats.count, 2);
    // Aggregates merge with the stored ones exactly (Chan et al.): {-60,-64} + {-62 ×2}.
    api::ScanUpload agg;
    agg.measurements = {{"wifi", "aa:bb:cc:dd:ee:01", {-62.0, 0.0, 2}}};
    const auto third = c.upload(rp.id, agg);
    EXPECT_TRUE(third.applied);
    EXPECT_DOUBLE_EQ(third.rp.measurements[0].stats.mean, -62.0);
    EXPECT_DOUBLE_EQ(third.rp.measurements[0].stats.variance, 2.0);  // (4+4+0+0)/4
    EXPECT_EQ(third.rp.measurements[0].stats.count, 4);
}

TEST(ApiClient, ExportImportAndLocalize) {
    ServerProcess server{{"--quiet"}};
    api::Client c(fast_retries(server.url()));
    const Chain ch = make_chain(c);
    const auto west = c.create_rp(ch.radiomap.id, "west", 2.0, 5.0);
    const auto east = c.create_rp(ch.radiomap.id, "east", 18.0, 5.0);
    c.upload(west.id, {std::nullopt, {{{"wifi", "aa:00:00:00:00:01", -40.0}, {"wifi", "aa:00:00:00:00:02", -80.0}}}, {}});
    c.upload(east.id, {std::nullopt, {{{"wifi", "aa:00:00:00:00:01", -80.0}, {"wifi", "aa:00:00:00:00:02", -40.0}}}, {}});
    api::LocalizeRequest q;
    q.algorithm = "nn";
    q.scans = {{{"wifi", "aa:00:00:00:00:01", -78.0}, {"wifi", "aa:00:00:00:00:02", -42.0}}};
    const auto at = c.localize_radiomap(ch.radiomap.id, q);
    EXPECT_DOUBLE_EQ(at.at.x, 18.0);
    EXPECT_DOUBLE_EQ(at.at.y, 5.0);
    EXPECT_EQ(at.floor_id, ch.floor.id);
    EXPECT_EQ(at.matched_aps, 2);
    EXPECT_EQ(at.algorithm, "nn");
    EXPECT_EQ(at.rp_ids, (std::vector<long long>{east.id}));
    EXPECT_FALSE(at.room);  // the chain's floor has no rooms
    ASSERT_EQ(at.candidates.size(), 2u);
    EXPECT_EQ(at.candidates[0].rp_id, east.id);
    EXPECT_DOUBLE_EQ(at.candidates[0].at.x, 18.0);
    EXPECT_EQ(at.candidates[0].score, at.score);
    EXPECT_EQ(at.candidates[0].floor_id, ch.floor.id);
    EXPECT_EQ(at.candidates[0].matched_aps, 2);
    EXPECT_EQ(at.candidates[1].rp_id, west.id);
    const auto whole = c.localize_map(ch.map.id, q);
    EXPECT_DOUBLE_EQ(whole.at.x, 18.0);
    EXPECT_EQ(whole.building_id, ch.building.id);
    // Asked for nothing, the client names no algorithm, so the server's default applies.
    api::LocalizeRequest plain;
    plain.scans = q.scans;
    EXPECT_FALSE(json(plain).contains("algorithm"));
    EXPECT_EQ(json(q).at("algorithm"), "nn");
    EXPECT_NEAR(c.localize_radiomap(ch.radiomap.id, plain).at.x, 18.0, 0.5);  // bayes: a weighted estimate

    json doc = c.export_radiomap(ch.radiomap.id);
    EXPECT_EQ(doc["rps"].size(), 2u);
    doc["name"] = "copy";
    const auto copy = c.import_radiomap(ch.floor.id, doc);
    EXPECT_NE(copy.id, ch.radiomap.id);
    const auto rps = c.rps(copy.id);
    ASSERT_EQ(rps.size(), 2u);
    EXPECT_EQ(c.rp(rps[0].id).measurements.size(), 2u);
}

TEST(ApiClient, WritesNeedTheApiKey) {
    ServerProcess server{{"--quiet", "--api-key", "k1"}};
    api::Client anonymous(fast_retries(server.url()));
    try {
        anonymous.create_map("m");
        FAIL() << "a write without the key must be refused";
    } catch (const api::ApiError& e) {
        EXPECT_EQ(e.status(), 401);
        EXPECT_EQ(e.code(), "unauthorized");
    }
    auto opts = fast_retries(server.url());
    opts.api_key = "k1";
    api::Client keyed(opts);
    EXPECT_GT(keyed.create_map("m").id, 0);
    EXPECT_EQ(anonymous.maps().size(), 1u);  // reads need no key
}

TEST(ApiClient, RetriesServerErrorsAndTooManyRequests) {
    httplib::Server fake;
    std::atomic<int> calls{0};
    fake.Get("/v1/maps/1", [&](const httplib::Request&, httplib::Response& res) {
        const int n = ++calls;
        if (n == 1) res.status = 503;
        else if (n == 2) res.status = 429;
        else res.set_content(R"({"id":1,"name":"m","description":""})", "application/json");
    });
    fake.Get("/v1/maps/2", [&](const httplib::Request&, httplib::Response& res) {
        ++calls;
        res.status = 400;
        res.set_content(R"({"error":{"code":"bad_request","message":"no"}})", "application/json");
    });
    const int port = fake.bind_to_any_port("127.0.0.1");
    std::thread t([&] { fake.listen_after_bind(); });
    {
        api::Client c(fast_retries("http://127.0.0.1:" + std::to_string(port)));
        EXPECT_EQ(c.get("/v1/maps/1")["name"], "m");
        EXPECT_EQ(calls.load(), 3);
        EXPECT_EQ(c.retries(), 2);
        calls = 0;
        EXPECT_THROW(c.get("/v1/maps/2"), api::ApiError);
        EXPECT_EQ(calls.load(), 1);  // 4xx: asked once
    }  // the kept-alive connection closes here, so stop() does not wait for it
    fake.stop();
    t.join();
}

TEST(ApiClient, GivesUpWithANetworkErrorAfterItsAttempts) {
    const int port = free_port();
    api::Client c(fast_retries("http://127.0.0.1:" + std::to_string(port), 3));
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_THROW(c.get("/health"), api::NetworkError);
    EXPECT_EQ(c.retries(), 2);
    EXPECT_GE(std::chrono::steady_clock::now() - t0, (20ms + 40ms) / 2);  // two back-offs, at the least jitter
}

TEST(ApiClient, WaitsForAServerThatStartsLate) {
    // The real server, started 400 ms after the client began asking.
    const int port = free_port();
    const std::string dir = locus::testing::make_temp_dir();
    pid_t pid = -1;
    std::thread starter([&] {
        std::this_thread::sleep_for(400ms);
        pid = fork();
        if (pid == 0) {
            const std::string db = dir + "/late.db", p = std::to_string(port);
            execl(LOCUS_SERVER_BIN, LOCUS_SERVER_BIN, "--db", db.c_str(), "--port", p.c_str(), "--quiet", "--demo",
                  static_cast<char*>(nullptr));
            _exit(127);
        }
    });
    {
        // 40 attempts: 3.7 to 7.3 s of back-off, for a sanitized server making its demo map
        // with other tests on both cores (12, about a second, ran out once).
        api::Client c(fast_retries("http://127.0.0.1:" + std::to_string(port), 40));
        std::vector<api::MapInfo> maps;
        EXPECT_NO_THROW(maps = c.maps());
        starter.join();
        EXPECT_EQ(maps.size(), 1u);  // the demo map
        EXPECT_GE(c.retries(), 1);
    }  // closes the kept-alive connection, which the server would otherwise wait for on SIGTERM
    if (pid > 0) {
        kill(pid, SIGTERM);
        waitpid(pid, nullptr, 0);
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace api_client_test
