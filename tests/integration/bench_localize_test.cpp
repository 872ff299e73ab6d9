// `locus bench localize` against the real server: the load generator's keep-alive connection,
// the JSON it prints, and what it refuses.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "bench_connection.hpp"
#include "hierarchy.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace bench_localize_test {
namespace {

using locus::testing::run_command;
using locus::testing::ServerProcess;
using locus::tools::BenchConnection;
using locus::tools::http_request;
using nlohmann::json;

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

// A loopback port nobody listens on: bound, then released.
int free_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    ::close(fd);
    return ntohs(a.sin_port);
}

// A one-connection server that answers each request with the next of `answers`, written one
// byte per send() so the client sees every answer arrive in pieces.
class ScriptedServer {
public:
    explicit ScriptedServer(std::vector<std::string> answers) : answers_(std::move(answers)) {
        listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t len = sizeof a;
        ::bind(listener_, reinterpret_cast<sockaddr*>(&a), sizeof a);
        ::listen(listener_, 1);
        ::getsockname(listener_, reinterpret_cast<sockaddr*>(&a), &len);
        port_ = ntohs(a.sin_port);
        thread_ = std::thread([this] {
            const int fd = ::accept(listener_, nullptr, nullptr);
            const int one = 1;
            ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            std::string in;
            char buf[4096];
            for (const auto& answer : answers_) {
                while (in.find("\r\n\r\n") == std::string::npos) {
                    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
                    if (n <= 0) {
                        ::close(fd);
                        return;
                    }
                    in.append(buf, static_cast<std::size_t>(n));
                }
                in.erase(0, in.find("\r\n\r\n") + 4);
                for (char c : answer) ::send(fd, &c, 1, MSG_NOSIGNAL);
            }
            ::close(fd);
        });
    }
    ~ScriptedServer() {
        thread_.join();
        ::close(listener_);
    }
    int port() const { return port_; }

private:
    std::vector<std::string> answers_;
    int listener_ = -1, port_ = 0;
    std::thread thread_;
};

TEST(BenchConnectionRefused, NoServerIsANetworkError) {
    const int port = free_port();
    BenchConnection c("127.0.0.1", port);
    EXPECT_EQ(c.round_trip(http_request("GET", "/health", "127.0.0.1:" + std::to_string(port))), std::nullopt);
}

TEST(BenchConnectionScripted, AnswersInPiecesAndAnswersItCannotDelimit) {
    ScriptedServer server({"HTTP/1.1 200 OK\r\nContent-Length: 5\r\n\r\nhello",
                           "HTTP/1.1 422 Unprocessable\r\ncontent-length:2\r\n\r\n{}",
                           "HTTP/1.1 200 OK\r\nContent-Type: text/plain\r\n\r\nno length"});
    BenchConnection c("127.0.0.1", server.port());
    const std::string get = http_request("GET", "/", "127.0.0.1");
    EXPECT_EQ(c.round_trip(get), 200);
    EXPECT_EQ(c.round_trip(get), 422);
    EXPECT_EQ(c.round_trip(get), std::nullopt);  // no Content-Length: its end is unknowable
}

TEST(BenchConnectionScripted, AnswersItCannotReadAreErrors) {
    for (const char* answer : {
             "HTTP/1.1 200 OK\r\nTransfer-Encoding: chunked\r\n\r\n5\r\nhello\r\n0\r\n\r\n",  // chunked
             "SSH-2.0-OpenSSH\r\n\r\n",                                                   // not HTTP
             "HTTP/1.1 200 OK\r\nContent-Length: 2abc\r\n\r\nok",                          // not a number
             "HTTP/1.1 200 OK\r\nContent-Length: 2\r\nContent-Length:\t3\r\n\r\nok!",      // two lengths
         }) {
        ScriptedServer server({answer});
        BenchConnection c("127.0.0.1", server.port());
        EXPECT_EQ(c.round_trip(http_request("GET", "/", "127.0.0.1")), std::nullopt) << answer;
    }
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
    ASSERT_EQ(out.at("ratio_by_round").size(), 5u);  // the default --rounds: 60 of each kind a round
    for (const auto& r : out.at("ratio_by_round")) EXPECT_GT(r.get<double>(), 0.0);
    EXPECT_NEAR(out.at("localize_over_health").get<double>(),
                out.at("localize").at("req_per_s").get<double>() / out.at("health").at("req_per_s").get<double>(), 1e-9);
}

// Every other scan is larger than the server accepts (413): those requests are counted as
// errors, left out of the figures, and the command fails after printing them.
TEST(BenchFailures, FailedRequestsAreCountedAndFailTheCommand) {
    ServerProcess s({"--max-body-bytes", "1000"});
    const auto h = locus::testing::make_hierarchy(s);
    const auto r = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import",
                          {{"name", "corridor"}, {"rps", {rp("west", 2, -40, -70), rp("east", 18, -70, -40)}}});
    ASSERT_EQ(r.status, 201) << r.raw;
    const std::string scans = locus::testing::make_temp_dir() + "/scans.jsonl";
    {
        std::ofstream out(scans);
        out << R"({"rp":"a","x":1,"y":1,"t":1,"readings":[{"bssid":"aa:00:00:00:00:01","rss":-41}]})" << "\n";
        out << R"({"rp":"a","x":1,"y":1,"t":2,"readings":[{"bssid":"aa:00:00:00:00:01","rss":-41})";
        for (int i = 0; i < 40; ++i) out << R"(,{"bssid":"bb:00:00:00:00:)" << 10 + i << R"(","rss":-80})";
        out << "]}\n";
    }
    const auto run = run_command({LOCUS_CLI_BIN, "bench", "localize", "--server", s.url(), "--radiomap",
                                  std::to_string(r.body.at("id").get<std::int64_t>()), "--scans", scans, "--concurrency", "1",
                                  "--requests", "100", "--rounds", "1"});
    EXPECT_NE(run.status, 0);
    EXPECT_NE(run.err.find("50 requests failed"), std::string::npos) << run.err;
    const json out = json::parse(run.out);
    EXPECT_EQ(out.at("localize").at("requests"), 100);
    EXPECT_EQ(out.at("localize").at("errors"), 50);
    EXPECT_EQ(out.at("health").at("errors"), 0);
    EXPECT_EQ(out.at("distinct_scans"), 2);
}

TEST_F(Bench, RefusesAnUnknownRadioMapAndARemoteServer) {
    const auto unknown = run_command({LOCUS_CLI_BIN, "bench", "localize", "--server", s.url(), "--radiomap", "999999", "--requests", "10"});
    EXPECT_NE(unknown.status, 0);
    EXPECT_NE(unknown.err.find("999999"), std::string::npos) << unknown.err;
    const auto remote = run_command({LOCUS_CLI_BIN, "bench", "localize", "--server", "http://192.0.2.1:80", "--radiomap", "1", "--requests", "10"});
    EXPECT_NE(remote.status, 0);
    EXPECT_NE(remote.err.find("loopback"), std::string::npos) << remote.err;
    const auto bad_port = run_command({LOCUS_CLI_BIN, "bench", "localize", "--server", "http://127.0.0.1:70000", "--radiomap", "1"});
    EXPECT_NE(bad_port.status, 0);
    EXPECT_NE(bad_port.err.find("port"), std::string::npos) << bad_port.err;
}

// `locus bench connections`: a short, small run of every kind of client.
TEST_F(Bench, ConnectionsReportsEveryKindOfClient) {
    const auto r = run_command({LOCUS_CLI_BIN, "bench", "connections", "--server", s.url(), "--radiomap", std::to_string(rm),
                                "--active", "2", "--idle", "3", "--slowloris", "1", "--seconds", "2", "--idle-interval",
                                "0.5", "--probe-interval", "0.1", "--algorithm", "nn"});
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    EXPECT_EQ(out.at("connections"), 6);
    EXPECT_EQ(out.at("localize").at("errors"), 0);
    EXPECT_GT(out.at("localize").at("requests").get<int>(), 0);
    EXPECT_LE(out.at("localize").at("p50_ms").get<double>(), out.at("localize").at("p99_ms").get<double>());
    EXPECT_EQ(out.at("fresh_health").at("failures"), 0);
    EXPECT_GT(out.at("fresh_health").at("probes").get<int>(), 5);
    EXPECT_EQ(out.at("idle").at("errors"), 0);
    EXPECT_EQ(out.at("idle").at("failed_to_open"), 0);
    EXPECT_GT(out.at("idle").at("requests").get<int>(), 0);
    EXPECT_EQ(out.at("slowloris").at("clients"), 1);
}

// Past the server's connection cap the idle clients are refused (503): counted, and the
// command fails after printing its figures.
TEST(BenchFailures, ConnectionsPastTheServersCapFailTheCommand) {
    ServerProcess s({"--max-connections", "3"});
    const auto h = locus::testing::make_hierarchy(s);
    const auto r = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import",
                          {{"name", "corridor"}, {"rps", {rp("west", 2, -40, -70), rp("east", 18, -70, -40)}}});
    ASSERT_EQ(r.status, 201) << r.raw;
    const auto run = run_command({LOCUS_CLI_BIN, "bench", "connections", "--server", s.url(), "--radiomap",
                                  std::to_string(r.body.at("id").get<std::int64_t>()), "--active", "1", "--idle", "4",
                                  "--slowloris", "0", "--seconds", "1"});
    EXPECT_NE(run.status, 0);
    EXPECT_NE(run.err.find("failed or timed out"), std::string::npos) << run.err;
    const json out = json::parse(run.out);
    EXPECT_GE(out.at("idle").at("failed_to_open").get<int>(), 1);
}

TEST_F(Bench, ConnectionsRefusesAnUnknownRadioMapAndARemoteServer) {
    const auto unknown = run_command({LOCUS_CLI_BIN, "bench", "connections", "--server", s.url(), "--radiomap", "999999"});
    EXPECT_NE(unknown.status, 0);
    EXPECT_NE(unknown.err.find("999999"), std::string::npos) << unknown.err;
    const auto remote = run_command({LOCUS_CLI_BIN, "bench", "connections", "--server", "http://192.0.2.1:80", "--radiomap", "1"});
    EXPECT_NE(remote.status, 0);
    EXPECT_NE(remote.err.find("loopback"), std::string::npos) << remote.err;
}

}  // namespace
}  // namespace bench_localize_test
