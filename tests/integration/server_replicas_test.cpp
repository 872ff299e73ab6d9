// Many servers, one PostgreSQL database (docs/deploy.md, "Replicated"): a write on one server
// reaches localize on another within a second, uploads from several servers to the same RPs merge
// exactly, a server killed mid-upload loses nothing it acknowledged, and a live track takes a
// phone's fixes on either server. Runs only under scripts/with_postgres.sh (LOCUS_TEST_DB_URL); an
// SQLite file has one server.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "track_call.hpp"

namespace server_replicas_test {
namespace {

using locus::testing::body_of;
using locus::testing::Response;
using locus::testing::SameDatabase;
using locus::testing::ServerProcess;
using locus::testing::track_call;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

json m(const std::string& bssid, double rss) { return {{"type", "wifi"}, {"bssid", bssid}, {"mean", rss}, {"variance", 1.0}, {"count", 10}}; }

json corridor() {
    return {{"name", "corridor"},
            {"rps",
             {{{"name", "west"}, {"x", 2.0}, {"y", 5.0}, {"scans", 10}, {"measurements", {m("aa:00:00:00:00:01", -40), m("aa:00:00:00:00:02", -70)}}},
              {{"name", "east"}, {"x", 18.0}, {"y", 5.0}, {"scans", 10}, {"measurements", {m("aa:00:00:00:00:01", -70), m("aa:00:00:00:00:02", -40)}}}}}};
}

json scan(double ap1, double ap2) {
    return {{"algorithm", "nn"},
            {"scans", json::array({json::array({{{"bssid", "aa:00:00:00:00:01"}, {"rss", ap1}}, {{"bssid", "aa:00:00:00:00:02"}, {"rss", ap2}}})})}};
}

// Polls `probe` until it holds or `limit` has passed since `since`; answers whether it held.
template <typename Probe>
bool within(Clock::time_point since, std::chrono::milliseconds limit, Probe probe) {
    while (Clock::now() - since < limit) {
        if (probe()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return probe();
}

struct Replicas : ::testing::Test {
    void SetUp() override {
        if (!locus::testing::on_postgres())
            GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)";
        a = std::make_unique<ServerProcess>(std::vector<std::string>{"--quiet"});
        b = std::make_unique<ServerProcess>(std::vector<std::string>{"--quiet"}, SameDatabase{a->db()});
    }
    void TearDown() override {
        b.reset();  // before a, whose database it uses
        a.reset();
    }
    std::unique_ptr<ServerProcess> a, b;
};

// One upload of one scan: RSS values from the upload's number, so a single-server replay is exact.
json upload(const std::string& id, int n) {
    return {{"upload_id", id},
            {"scans", json::array({json::array({{{"type", "wifi"}, {"bssid", "bb:00:00:00:00:01"}, {"rss", -50 - (n % 17)}},
                                                {{"type", "wifi"}, {"bssid", "bb:00:00:00:00:02"}, {"rss", -60 - (n % 11)}}})})}};
}

// "u7", "0-1-12": appended one by one (GCC 12 warns falsely on "u" + std::to_string(n)).
std::string id_of(std::initializer_list<int> parts, const char* prefix = "") {
    std::string out = prefix;
    for (const int p : parts) {
        if (out.size() > std::string_view(prefix).size()) out += '-';
        out += std::to_string(p);
    }
    return out;
}

TEST_F(Replicas, AWriteOnOneServerReachesLocalizeOnTheOtherWithinASecond) {
    const auto h = locus::testing::make_hierarchy(*a);
    const auto imported = a->post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", corridor());
    ASSERT_EQ(imported.status, 201) << imported.raw;
    const auto written = Clock::now();
    const std::string path = "/v1/radiomaps/" + std::to_string(imported.body.at("id").get<long long>()) + "/localize";
    EXPECT_TRUE(within(written, std::chrono::milliseconds(1000), [&] {
        const auto r = b->post(path, scan(-41, -69));
        return r.status == 200 && r.body.at("x").get<double>() == 2.0;
    })) << "B does not localize on the radio map A imported";

    // A new RP whose scans match best: B's answer moves to it.
    const auto rp = locus::testing::make_rp(*a, imported.body.at("id").get<long long>(), "far", 30.0, 5.0);
    const json scans = {{"scans", json::array({json::array({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -20}}, {{"bssid", "aa:00:00:00:00:02"}, {"rss", -20}}})})}};
    ASSERT_EQ(a->post("/v1/rps/" + std::to_string(rp) + "/scans", scans).status, 200);
    const auto uploaded = Clock::now();
    EXPECT_TRUE(within(uploaded, std::chrono::milliseconds(1000), [&] {
        const auto r = b->post(path, scan(-20, -20));
        return r.status == 200 && r.body.at("x").get<double>() == 30.0;
    })) << "B does not see the RP and upload written on A";

    // A delete on B: A stops answering for the radio map.
    ASSERT_EQ(b->del("/v1/maps/" + std::to_string(h.map)).status, 204);
    const auto deleted = Clock::now();
    EXPECT_TRUE(within(deleted, std::chrono::milliseconds(1000), [&] { return a->post(path, scan(-20, -20)).status == 404; }))
        << "A still localizes on a map deleted on B";
}

TEST_F(Replicas, UploadsFromTwoServersToTheSameRpsMergeAsOnOneServer) {
    const auto h = locus::testing::make_hierarchy(*a);
    std::vector<std::int64_t> rps;
    for (int i = 0; i < 3; ++i) rps.push_back(locus::testing::make_rp(*a, h.radiomap, id_of({i}, "rp-"), i, 0));
    // 4 clients on each server, every upload sent twice (a retry: the second must change nothing).
    constexpr int kClients = 4, kUploads = 12;
    std::atomic<int> failures{0};
    std::vector<std::thread> clients;
    for (int server = 0; server < 2; ++server)
        for (int c = 0; c < kClients; ++c)
            clients.emplace_back([&, server, c] {
                const ServerProcess& s = server == 0 ? *a : *b;
                const ServerProcess& other = server == 0 ? *b : *a;
                for (int k = 0; k < kUploads; ++k) {
                    const int n = (server * kClients + c) * kUploads + k;
                    const auto body = upload(id_of({n}, "u"), n);
                    const std::string path = "/v1/rps/" + std::to_string(rps[static_cast<std::size_t>(n) % rps.size()]) + "/scans";
                    const auto first = s.post(path, body), again = other.post(path, body);
                    if (first.status != 200 || again.status != 200 || again.body.at("applied").get<bool>()) ++failures;
                }
            });
    for (auto& t : clients) t.join();
    EXPECT_EQ(failures.load(), 0);

    // The same uploads, one after another, on one server of its own.
    ServerProcess single({"--quiet"});
    const auto h1 = locus::testing::make_hierarchy(single);
    std::vector<std::int64_t> rps1;
    for (int i = 0; i < 3; ++i) rps1.push_back(locus::testing::make_rp(single, h1.radiomap, id_of({i}, "rp-"), i, 0));
    for (int n = 0; n < 2 * kClients * kUploads; ++n)
        ASSERT_EQ(single.post("/v1/rps/" + std::to_string(rps1[static_cast<std::size_t>(n) % 3]) + "/scans", upload(id_of({n}, "u"), n)).status, 200);

    for (std::size_t i = 0; i < rps.size(); ++i) {
        const auto got = body_of(b->get("/v1/rps/" + std::to_string(rps[i])));
        const auto want = body_of(single.get("/v1/rps/" + std::to_string(rps1[i])));
        EXPECT_EQ(got.at("scans"), want.at("scans"));
        ASSERT_EQ(got.at("measurements").size(), want.at("measurements").size());
        for (std::size_t j = 0; j < want.at("measurements").size(); ++j) {
            const auto& g = got.at("measurements")[j];
            const auto& w = want.at("measurements")[j];
            EXPECT_EQ(g.at("bssid"), w.at("bssid"));
            EXPECT_EQ(g.at("count"), w.at("count"));
            // Welford in another order rounds differently in the last bits, no more.
            EXPECT_NEAR(g.at("mean").get<double>(), w.at("mean").get<double>(), 1e-9);
            EXPECT_NEAR(g.at("variance").get<double>(), w.at("variance").get<double>(), 1e-9);
        }
    }
}

TEST_F(Replicas, AServerKilledMidUploadLosesNothingItAcknowledged) {
    const auto h = locus::testing::make_hierarchy(*a);
    const auto rp = locus::testing::make_rp(*a, h.radiomap, "rp", 1, 1);
    const std::string path = "/v1/rps/" + std::to_string(rp) + "/scans";
    std::mutex mu;
    std::set<std::string> acknowledged, sent;
    std::atomic<bool> stop{false};
    std::vector<std::thread> clients;
    for (int server = 0; server < 2; ++server)
        for (int c = 0; c < 2; ++c)
            clients.emplace_back([&, server, c] {
                const ServerProcess& s = server == 0 ? *a : *b;
                for (int k = 0; !stop; ++k) {
                    const std::string id = id_of({server, c, k});
                    {
                        std::lock_guard lock(mu);
                        sent.insert(id);
                    }
                    const auto r = s.post(path, upload(id, k));
                    if (r.status == 200) {
                        std::lock_guard lock(mu);
                        acknowledged.insert(id);
                    }
                    if (r.status == 0 && server == 0) return;  // A is gone
                }
            });
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    a->kill9();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    stop = true;
    for (auto& t : clients) t.join();
    ASSERT_GT(acknowledged.size(), 0u);

    // Every acknowledged upload is stored: sent again to B, it is a repeat.
    for (const auto& id : acknowledged) {
        const auto r = b->post(path, upload(id, 0));
        ASSERT_EQ(r.status, 200) << r.raw;
        EXPECT_FALSE(r.body.at("applied").get<bool>()) << "acknowledged upload " << id << " was lost";
    }
    // And nothing was stored twice or from nowhere: one scan per distinct upload.
    const auto stored = body_of(b->get("/v1/rps/" + std::to_string(rp)));
    EXPECT_GE(stored.at("scans").get<std::size_t>(), acknowledged.size());
    EXPECT_LE(stored.at("scans").get<std::size_t>(), sent.size());
}

TEST_F(Replicas, AChangeWhoseNotificationNeverCameIsSeenByTheCounter) {
    const auto h = locus::testing::make_hierarchy(*a);
    const auto imported = a->post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", corridor());
    ASSERT_EQ(imported.status, 201) << imported.raw;
    const std::string path = "/v1/radiomaps/" + std::to_string(imported.body.at("id").get<long long>()) + "/localize";
    ASSERT_TRUE(within(Clock::now(), std::chrono::milliseconds(1000), [&] {
        const auto r = b->post(path, scan(-41, -69));
        return r.status == 200 && r.body.at("x").get<double>() == 2.0;
    }));
    // A write that sends no NOTIFY (as if the notification were lost): only the counter moves.
    locus::testing::database_exec(a->db(), "BEGIN; UPDATE rps SET x = 4 WHERE name = 'west'; "
                                            "UPDATE change_counter SET version = version + 1; COMMIT");
    const auto written = Clock::now();
    EXPECT_TRUE(within(written, std::chrono::milliseconds(1500), [&] {
        const auto r = b->post(path, scan(-41, -69));
        return r.status == 200 && r.body.at("x").get<double>() == 4.0;
    })) << "B never noticed the change the counter announced";
}

TEST_F(Replicas, ALiveTrackTakesFixesOnEitherServer) {
    const auto h = locus::testing::make_hierarchy(*a);
    const json opened = body_of(a->post("/v1/tracks", {{"map_id", h.map}, {"label", "phone"}}), 201);
    const std::string path = "/v1/tracks/" + std::to_string(opened.at("id").get<std::int64_t>());
    const std::string token = opened.at("token").get<std::string>();
    const double t0 = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count() - 10;
    // The phone's requests alternate between the servers, as behind a load balancer.
    for (int i = 0; i < 6; ++i) {
        const ServerProcess& s = i % 2 ? *b : *a;
        const json fix = {{"t", t0 + i}, {"floor_id", h.floor}, {"x", 1.0 * i}, {"y", 0.0}, {"accuracy_m", 1.5}};
        const auto r = track_call(s, "POST", path + "/fixes", token, json{{"fixes", json::array({fix})}}.dump());
        ASSERT_EQ(r.status, 200) << "fix " << i << ": " << r.raw;
        EXPECT_EQ(r.body.at("stored"), 1);
    }
    for (const ServerProcess* s : {a.get(), b.get()}) {
        const json got = body_of(track_call(*s, "GET", path, token));
        EXPECT_EQ(got.at("fixes"), 6);
        EXPECT_EQ(got.at("latest").at("x"), 5.0);
        EXPECT_EQ(got.at("trail").size(), 6u);
    }
    // A thin client's steps alternate too: each server goes on from the track's latest stored
    // fix, whichever server stored it (it holds no filter, or one the other server passed).
    for (int i = 6; i < 10; ++i) {
        const ServerProcess& s = i % 2 ? *b : *a;
        const json step = {{"t", t0 + i}, {"length_m", 0.7}, {"heading_deg", 0.0}};
        const auto r = track_call(s, "POST", path + "/steps", token, json{{"steps", json::array({step})}}.dump());
        ASSERT_EQ(r.status, 200) << "step " << i << ": " << r.raw;
        EXPECT_EQ(r.body.at("stored"), 1);
        EXPECT_EQ(r.body.at("fused").size(), 1u);
    }
    EXPECT_EQ(body_of(track_call(*a, "GET", path, token)).at("fixes"), 10);
    // Closed on one server, the track takes no fix on the other.
    EXPECT_EQ(body_of(track_call(*b, "POST", path + "/close", token, "{}")).at("state"), "closed");
    const json late = {{"t", t0 + 7}, {"floor_id", h.floor}, {"x", 7.0}, {"y", 0.0}, {"accuracy_m", 1.5}};
    const auto refused = track_call(*a, "POST", path + "/fixes", token, json{{"fixes", json::array({late})}}.dump());
    EXPECT_EQ(refused.status, 409) << refused.raw;
    EXPECT_EQ(refused.body.at("error").at("code"), "track_closed") << refused.raw;
}

}  // namespace
}  // namespace server_replicas_test
