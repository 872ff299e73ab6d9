// `locus bench localize` against the real server: the load generator's keep-alive connection,
// the JSON it prints, and what it refuses.
#include <gtest/gtest.h>

#include "bench_connection.hpp"
#include "hierarchy.hpp"
#include "server_process.hpp"

using locus::testing::run_command;
using locus::testing::ServerProcess;
using locus::tools::BenchConnection;
using locus::tools::http_request;
using nlohmann::json;

namespace {

json rp(const std::string& name, double x, double ap1, double ap2) {
    auto m = [](const char* bssid, double mean) {
        return json{{"bssid", bssid}, {"mean", mean}, {"variance", 4.0}, {"count", 10}};
    };
    return {{"name", name}, {"x", x}, {"y", 5.0}, {"scans", 10},
            {"measurements", {m("aa:00:00:00:00:01", ap1), m("aa:00:00:00:00:02", ap2)}}};
}

struct Bench : ::testing::Test {
    ServerProcess s;
    locus::testing::Hierarchy h = locus::testing::make_hierarchy(s);
    std::int64_t rm = 0;
    void SetUp() override {
        const auto r = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import",
                              {{"name", "corridor"}, {"rps", {rp("west", 2, -40, -70), rp("east", 18, -70, -40)}}});
        ASSERT_EQ(r.status, 201) << r.raw;
        rm = r.body.at("id").get<std::int64_t>();
    }
    std::string host_port() const { return "127.0.0.1:" + std::to_string(s.port()); }
};

}  // namespace

TEST_F(Bench, ConnectionKeepsAliveAndReportsStatuses) {
    BenchConnection c("127.0.0.1", s.port());
    EXPECT_EQ(c.round_trip(http_request("GET", "/health", host_port())), 200);
    const std::string body = R"({"algorithm":"nn","scans":[[{"bssid":"aa:00:00:00:00:01","rss":-41}]]})";
    const std::string path = "/v1/radiomaps/" + std::to_string(rm) + "/localize";
    EXPECT_EQ(c.round_trip(http_request("POST", path, host_port(), body)), 200);
    EXPECT_EQ(c.round_trip(http_request("POST", path, host_port(), "{")), 400);  // the answer body is consumed too
    EXPECT_EQ(c.round_trip(http_request("GET", "/v1/radiomaps/999999", host_port())), 404);
    EXPECT_EQ(c.round_trip(http_request("GET", "/health", host_port())), 200);
}

TEST_F(Bench, ConnectionReopensAfterTheServerCloses) {
    BenchConnection c("127.0.0.1", s.port());
    std::string closing = http_request("GET", "/health", host_port());
    closing.insert(closing.size() - 2, "Connection: close\r\n");
    for (int i = 0; i < 3; ++i) EXPECT_EQ(c.round_trip(closing), 200) << "round " << i;
    EXPECT_EQ(c.round_trip(http_request("GET", "/health", host_port())), 200);
}

TEST(BenchConnectionRefused, NoServerIsANetworkError) {
    BenchConnection c("127.0.0.1", 1);  // nothing listens on port 1 here
    EXPECT_EQ(c.round_trip(http_request("GET", "/health", "127.0.0.1:1")), std::nullopt);
}

TEST_F(Bench, PrintsThroughputAndLatencyForLocalizeAndHealth) {
    const auto r = run_command({LOCUS_CLI_BIN, "bench", "localize", "--server", s.url(), "--radiomap", std::to_string(rm),
                                "--concurrency", "2", "--requests", "300", "--algorithm", "nn"});
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    for (const char* phase : {"localize", "health"}) {
        const json& p = out.at(phase);
        EXPECT_EQ(p.at("requests"), 300) << phase;
        EXPECT_EQ(p.at("errors"), 0) << phase;
        EXPECT_GT(p.at("req_per_s").get<double>(), 0.0) << phase;
        EXPECT_LE(p.at("p50_ms").get<double>(), p.at("p99_ms").get<double>()) << phase;
    }
    EXPECT_EQ(out.at("distinct_scans"), 2);  // one per RP: its own means
    EXPECT_NEAR(out.at("localize_over_health").get<double>(),
                out.at("localize").at("req_per_s").get<double>() / out.at("health").at("req_per_s").get<double>(), 1e-9);
}

TEST_F(Bench, RefusesAnUnknownRadioMapAndARemoteServer) {
    const auto unknown = run_command({LOCUS_CLI_BIN, "bench", "localize", "--server", s.url(), "--radiomap", "999999", "--requests", "10"});
    EXPECT_NE(unknown.status, 0);
    EXPECT_NE(unknown.err.find("999999"), std::string::npos) << unknown.err;
    const auto remote = run_command({LOCUS_CLI_BIN, "bench", "localize", "--server", "http://192.0.2.1:80", "--radiomap", "1", "--requests", "10"});
    EXPECT_NE(remote.status, 0);
    EXPECT_NE(remote.err.find("loopback"), std::string::npos) << remote.err;
}
