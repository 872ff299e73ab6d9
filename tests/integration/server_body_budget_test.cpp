// Request bodies and answers in flight (http/front/body_budget.hpp, docs/deploy.md "Request
// bodies in flight"): a
// client's bodies being received and parsed hold its share until answered (429
// too_many_bodies past it), all clients' the server-wide budget (503 server_busy), each refused
// before its body is read; and a body must come at --min-body-rate (408 past its time). An
// answer not yet read holds its client's answer share (429 too_many_answers) until written or
// cut at its deadline.
#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>

#include "hierarchy.hpp"
#include "plan_geojson.hpp"
#include "raw_connection.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_body_budget_test {
namespace {

using locus::testing::raw_post;
using locus::testing::RawConnection;
using locus::testing::ServerProcess;
using nlohmann::json;

// A localize body of about `bytes`: one scan, padded with whitespace (valid JSON).
std::string body_of(std::size_t bytes) {
    const std::string scan = R"({"scans":[[{"bssid":"aa:00:00:00:00:01","rss":-50}]]})";
    return scan + std::string(bytes > scan.size() ? bytes - scan.size() : 0, ' ');
}

struct Answer {
    int status = 0;
    std::string code, message, retry_after;
    std::size_t bytes = 0;  // of the body
};

// One request on a connection of its own from `source`: a POST of `body`, or a GET without one.
// Up to 120 s for its answer: a large plan's is built in seconds under sanitizers.
Answer request_from(const ServerProcess& s, const std::string& source, const std::string& path, const std::optional<std::string>& body) {
    httplib::Client c("127.0.0.1", s.port());
    c.set_interface(source);
    c.set_read_timeout(120, 0);
    const auto r = body ? c.Post(path.c_str(), *body, "application/json") : c.Get(path.c_str());
    if (!r) return {};
    Answer a{r->status, "", "", r->get_header_value("Retry-After"), r->body.size()};
    const json j = json::parse(r->body, nullptr, false);
    if (j.is_object() && j.contains("error")) {
        a.code = j["error"].value("code", "");
        a.message = j["error"].value("message", "");
    }
    return a;
}

Answer post_from(const ServerProcess& s, const std::string& source, const std::string& path, const std::string& body) {
    return request_from(s, source, path, body);
}
Answer get_from(const ServerProcess& s, const std::string& source, const std::string& path) {
    return request_from(s, source, path, std::nullopt);
}

// Refused before its body was read: `status` and `code`, the message naming `flag`, Retry-After: 1.
void expect_refused(const Answer& a, int status, const std::string& code, const std::string& flag) {
    EXPECT_EQ(a.status, status) << a.message;
    EXPECT_EQ(a.code, code);
    EXPECT_NE(a.message.find(flag), std::string::npos) << a.message;
    EXPECT_EQ(a.retry_after, "1");
}

// A request whose body is sent but for its last byte: the server holds it in flight.
struct HeldBody {
    HeldBody(const ServerProcess& s, const std::string& path, std::size_t bytes) : connection(s.port()), request(raw_post(path, body_of(bytes))) {
        EXPECT_TRUE(connection.send(request.substr(0, request.size() - 1)));
        std::this_thread::sleep_for(std::chrono::milliseconds(200));  // read up to there: admitted
    }
    int finish() {
        connection.send(request.substr(request.size() - 1));
        const auto a = connection.read_answer();
        return a ? a->status : 0;
    }
    RawConnection connection;
    std::string request;
};

TEST(ServerBodyBudget, AClientsBodiesInFlightHoldItsShareUntilAnswered) {
    ServerProcess s({"--quiet", "--client-body-bytes-in-flight", "300000", "--max-body-bytes-in-flight", "1000000"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string path = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize";
    HeldBody held(s, path, 200'000);
    expect_refused(post_from(s, "127.0.0.1", path, body_of(150'000)), 429, "too_many_bodies", "--client-body-bytes-in-flight 300000");
    // What still fits the share, and another client's body, pass.
    EXPECT_NE(post_from(s, "127.0.0.1", path, body_of(50'000)).status, 429);
    EXPECT_NE(post_from(s, "127.0.0.2", path, body_of(150'000)).status, 429);
    // Answered, the held body gives its bytes back.
    const int held_status = held.finish();
    EXPECT_NE(held_status, 0);
    EXPECT_NE(held_status, 429);
    EXPECT_NE(post_from(s, "127.0.0.1", path, body_of(150'000)).status, 429);
}

TEST(ServerBodyBudget, EveryClientTogetherMeetsTheServerWideBudget) {
    ServerProcess s({"--quiet", "--client-body-bytes-in-flight", "300000", "--max-body-bytes-in-flight", "300000"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string path = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize";
    HeldBody held(s, path, 200'000);
    expect_refused(post_from(s, "127.0.0.2", path, body_of(150'000)), 503, "server_busy", "--max-body-bytes-in-flight 300000");
    EXPECT_NE(held.finish(), 0);
    EXPECT_NE(post_from(s, "127.0.0.2", path, body_of(150'000)).status, 503);
}

TEST(ServerBodyBudget, ABodySlowerThanTheMinimumRateIsDropped) {
    // 100,000 bytes at 50,000 bytes a second, after a 1 s read timeout: 3 s to come.
    ServerProcess s({"--quiet", "--min-body-rate", "50000", "--read-timeout", "1"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string request = raw_post("/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize", body_of(100'000));
    RawConnection c(s.port());
    ASSERT_TRUE(c.send(request.substr(0, request.size() - 200)));
    const auto start = std::chrono::steady_clock::now();
    // A byte every 0.3 s: never a pause as long as the read timeout, but far below the rate.
    std::optional<locus::testing::RawAnswer> answer;
    for (std::size_t i = request.size() - 200; i < request.size() - 1 && !answer; ++i) {
        if (!c.send(request.substr(i, 1))) break;
        answer = c.read_answer(std::chrono::milliseconds(300));
    }
    if (!answer) answer = c.read_answer(std::chrono::seconds(5));
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(answer.has_value()) << "no answer after " << waited << " s";
    EXPECT_EQ(answer->status, 408) << answer->body;
    EXPECT_LT(waited, 10.0);
}

// A floor plan of `walls` walls: a GET of it answers some 100 bytes a wall.
json many_walls(int walls) {
    json features = json::array();
    for (int i = 0; i < walls; ++i) {
        const double x = 0.5 + (i % 230) * 0.125, y = 0.5 + (i / 230) * 0.0625;  // short decimals
        features.push_back(locus::testing::feature("wall", locus::testing::line({{x, y}, {x, y + 0.03125}})));
    }
    return {{"type", "FeatureCollection"}, {"features", features}};
}

TEST(ServerAnswerBudget, AnAnswerNotReadHoldsItsClientsShareUntilCutAtItsDeadline) {
    // A 6 MB answer (more than the kernel buffers on loopback) at 2 MB a second, after the 10 s
    // write timeout: 13 s to be read.
    ServerProcess s({"--quiet", "--client-answer-bytes-in-flight", "400000", "--min-body-rate", "2000000"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string plan = "/v1/floors/" + std::to_string(h.floor) + "/plan";
    const json walls = many_walls(50'000);
    ASSERT_LT(walls.dump().size(), 8'000'000u);
    ASSERT_EQ(s.put(plan, walls).status, 200);
    const Answer whole = get_from(s, "127.0.0.1", plan);  // built, then kept
    ASSERT_EQ(whole.status, 200);
    ASSERT_GT(whole.bytes, 5'000'000u);
    // A reader that never reads: the server's write blocks on a full socket.
    RawConnection stuck(s.port(), 4096);
    ASSERT_TRUE(stuck.send(locus::testing::raw_get(plan)));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    expect_refused(get_from(s, "127.0.0.1", plan), 429, "too_many_answers", "--client-answer-bytes-in-flight 400000");
    EXPECT_EQ(get_from(s, "127.0.0.2", plan).status, 200);
    // Cut at its deadline, the stuck answer gives its bytes back.
    EXPECT_TRUE(stuck.closed_within(std::chrono::seconds(20)));
    EXPECT_EQ(get_from(s, "127.0.0.1", plan).status, 200);
}

TEST(ServerRequestSlots, AClientHasAFewRequestsHandledAtOnce) {
    ServerProcess s({"--quiet", "--client-requests-in-flight", "2"});
    const auto h = locus::testing::make_hierarchy(s);
    const std::string path = "/v1/radiomaps/" + std::to_string(h.radiomap) + "/localize";
    HeldBody a(s, path, 1000), b(s, path, 1000);  // two requests in flight, waiting on their last byte
    expect_refused(get_from(s, "127.0.0.1", "/v1/maps"), 429, "too_many_requests", "--client-requests-in-flight");
    EXPECT_EQ(get_from(s, "127.0.0.2", "/v1/maps").status, 200);
    EXPECT_NE(a.finish(), 0);
    EXPECT_EQ(get_from(s, "127.0.0.1", "/v1/maps").status, 200);
}

TEST(ServerBodyBudget, BadValuesAreRefusedAtStart) {
    for (const char* flag : {"--min-body-rate", "--max-body-bytes-in-flight", "--client-body-bytes-in-flight",
                             "--max-answer-bytes-in-flight", "--client-answer-bytes-in-flight", "--client-requests-in-flight"}) {
        const auto r = locus::testing::run_command({"/usr/bin/timeout", "10", LOCUS_SERVER_BIN, "--db", "/nonexistent/never.db",
                                                    "--port", "0", "--quiet", flag, "0"});
        EXPECT_NE(r.status, 0) << flag;
        EXPECT_NE((r.err + r.out).find(flag), std::string::npos) << flag << ": " << r.err << r.out;
    }
}

}  // namespace
}  // namespace server_body_budget_test
