// The connection layer against raw sockets: idle and slow clients, pipelining, lying or
// refused bodies, the connection cap, a shared port. Each case was seen failing with
// cpp-httplib's own connection handling.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "raw_connection.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_connections_test {
namespace {

using locus::testing::raw_get;
using locus::testing::raw_post;
using locus::testing::RawConnection;
using locus::testing::ServerProcess;
using nlohmann::json;
using namespace std::chrono_literals;

json map_count(const ServerProcess& s) { return s.get("/v1/maps").body.at("total"); }

// With cpp-httplib's fixed pool of --threads workers, that many idle keep-alive connections
// left every other client waiting (8.7 s for /health behind 8 idle connections).
TEST(Connections, IdleAndHalfSentRequestsDoNotStallOthers) {
    ServerProcess s({"--threads", "2"});
    std::vector<std::unique_ptr<RawConnection>> idle;
    for (int i = 0; i < 24; ++i) {
        idle.push_back(std::make_unique<RawConnection>(s.port()));
        ASSERT_TRUE(idle.back()->connected());
        if (i % 2 == 0) {  // a kept-alive client that has been answered once
            ASSERT_TRUE(idle.back()->send(raw_get("/health")));
            ASSERT_TRUE(idle.back()->read_answer());
        } else {  // a client that sent half a request head
            ASSERT_TRUE(idle.back()->send("GET /health HTTP/1.1\r\nHost: x"));
        }
    }
    RawConnection fresh(s.port());
    ASSERT_TRUE(fresh.send(raw_get("/v1/maps")));
    const auto answer = fresh.read_answer(3s);  // generous: the old server needed 10 s and more
    ASSERT_TRUE(answer) << "a new client was not answered while 24 connections sat idle";
    EXPECT_EQ(answer->status, 200);
}

TEST(Connections, PipelinedRequestsAreAnsweredInOrder) {
    ServerProcess s;
    RawConnection c(s.port());
    ASSERT_TRUE(c.send(raw_get("/health") + raw_get("/v1/maps/999") + raw_post("/v1/maps", R"({"name":"piped"})") +
                       raw_get("/v1/maps")));
    const int expected[] = {200, 404, 201, 200};
    for (int status : expected) {
        const auto a = c.read_answer(3s);
        ASSERT_TRUE(a) << "a pipelined request was not answered";
        EXPECT_EQ(a->status, status) << a->head;
    }
    EXPECT_EQ(map_count(s), 1);
}

// A 401 went out before the body was read, and the body was then parsed as the next request
// on the same connection: request smuggling behind a proxy that reuses connections.
TEST(Connections, ARefusedBodyIsNeverTakenForTheNextRequest) {
    ServerProcess s({"--api-key", "k"});
    const std::string smuggled = raw_get("/v1/maps/999");
    RawConnection c(s.port());
    ASSERT_TRUE(c.send(raw_post("/v1/maps", smuggled)));
    const auto refused = c.read_answer();
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 401);
    EXPECT_EQ(refused->header("Connection"), "close");
    EXPECT_FALSE(c.read_answer(1500ms)) << "the body was answered as a request";
    EXPECT_TRUE(c.closed_within(3s));

    // The same with the body sent after the refusal has arrived.
    RawConnection late(s.port());
    const std::string head = raw_post("/v1/maps", smuggled);
    ASSERT_TRUE(late.send(head.substr(0, head.size() - smuggled.size())));
    const auto refused_early = late.read_answer();
    ASSERT_TRUE(refused_early);
    EXPECT_EQ(refused_early->status, 401);
    late.send(smuggled);
    EXPECT_FALSE(late.read_answer(1500ms)) << "the late body was answered as a request";
}

TEST(Connections, AChunkedBodyCannotPassTheBodyLimit) {
    ServerProcess s({"--max-body-bytes", "4096"});
    const std::string big = R"({"name":"big","description":")" + std::string(20000, 'x') + R"("})";
    RawConnection c(s.port());
    ASSERT_TRUE(c.send(locus::testing::raw_chunked_post("/v1/maps", big, 1000)));
    const auto a = c.read_answer();
    ASSERT_TRUE(a);
    EXPECT_EQ(a->status, 413) << a->body;
    EXPECT_EQ(json::parse(a->body).at("error").at("code"), "payload_too_large");
    EXPECT_EQ(a->header("Connection"), "close");
    EXPECT_EQ(map_count(s), 0);

    // Far past the limit, reading stops on the wire (twice the limit and 64 KiB at most).
    RawConnection huge(s.port());
    const std::string very_big = R"({"name":"huge","description":")" + std::string(400000, 'x') + R"("})";
    huge.send(locus::testing::raw_chunked_post("/v1/maps", very_big, 4000));
    const auto refused = huge.read_answer();
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 413) << refused->body;

    // Within the limit, chunked is fine; the connection then closes (a chunked body's end is
    // cpp-httplib's to find, and it can be fooled), so the next request goes on a new one.
    RawConnection ok(s.port());
    ASSERT_TRUE(ok.send(locus::testing::raw_chunked_post("/v1/maps", R"({"name":"small"})", 5)));
    const auto created = ok.read_answer();
    ASSERT_TRUE(created);
    EXPECT_EQ(created->status, 201) << created->body;
    EXPECT_EQ(created->header("Connection"), "close");
    EXPECT_EQ(map_count(s), 1);
}

// cpp-httplib ends a chunked body at the first malformed chunk and reports success; whatever
// followed was then read as the next request.
TEST(Connections, AMalformedChunkedBodyEndsTheConnection) {
    ServerProcess s;
    RawConnection c(s.port());
    ASSERT_TRUE(c.send("POST /v1/maps HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                       "Transfer-Encoding: chunked\r\n\r\nd\r\n{\"name\":\"m1\"}XX\r\n" +
                       raw_get("/v1/maps/999")));
    const auto first = c.read_answer();
    ASSERT_TRUE(first);
    EXPECT_EQ(first->header("Connection"), "close");
    EXPECT_FALSE(c.read_answer(1500ms)) << "bytes after a broken chunk were answered as a request";
}

// A chunked body's length is known only once read: checked then, whatever its chunk sizes.
TEST(Connections, AChunkedBodyIsMeasuredDecoded) {
    ServerProcess s({"--max-body-bytes", "4096"});
    const std::string padded = R"({"name":"tiny chunks",)" + std::string(1400, ' ') + R"("description":"x"})";
    RawConnection c(s.port());
    ASSERT_TRUE(c.send(locus::testing::raw_chunked_post("/v1/maps", padded, 1)));  // ~9 kB on the wire, 1.4 kB of body
    const auto a = c.read_answer();
    ASSERT_TRUE(a);
    EXPECT_EQ(a->status, 201) << a->body;
}

TEST(Connections, ABodyTrickledAByteAtATimeIsCutOff) {
    ServerProcess s({"--read-timeout", "1"});
    RawConnection c(s.port());
    ASSERT_TRUE(c.send("POST /v1/maps HTTP/1.1\r\nHost: x\r\nContent-Length: 1000\r\n\r\n{"));
    const auto start = std::chrono::steady_clock::now();
    bool cut = false;
    for (int i = 0; i < 40 && !cut; ++i) {  // a byte every 300 ms never trips the per-read timeout
        if (!c.send(" ")) cut = true;
        else cut = c.closed_within(300ms);
    }
    EXPECT_TRUE(cut) << "a trickled body held its worker for 12 s";
    EXPECT_LT(std::chrono::steady_clock::now() - start, 8s);
}

// A client that asks before sending its body is refused before it sends it.
TEST(Connections, ExpectContinueIsAnsweredWithTheRefusal) {
    ServerProcess s({"--max-body-bytes", "4096", "--api-key", "k"});
    for (const std::string& extra : {std::string("Authorization: Bearer k\r\nContent-Length: 99999999\r\n"),
                                     std::string("Content-Length: 100\r\n")}) {
        RawConnection c(s.port());
        ASSERT_TRUE(c.send("POST /v1/maps HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\n" + extra + "\r\n"));
        const auto a = c.read_answer();
        ASSERT_TRUE(a);
        EXPECT_TRUE(a->status == 413 || a->status == 401) << a->head;
        EXPECT_EQ(a->head.find("100 Continue"), std::string::npos) << a->head;
    }
}

TEST(Connections, AnOversizedRequestLineIsAnswered) {
    ServerProcess s;
    RawConnection c(s.port());
    ASSERT_TRUE(c.send(raw_get("/" + std::string(70 * 1024, 'a'))));
    const auto a = c.read_answer();
    ASSERT_TRUE(a) << "the connection closed without an answer";
    EXPECT_TRUE(a->status == 414 || a->status == 431) << a->head;
}

TEST(Connections, ALengthOverTheLimitIsRefusedBeforeTheBodyIsRead) {
    ServerProcess s({"--max-body-bytes", "4096"});
    RawConnection c(s.port());
    ASSERT_TRUE(c.send("POST /v1/maps HTTP/1.1\r\nHost: x\r\nContent-Length: 67108864\r\n\r\n{\"name\":"));
    const auto a = c.read_answer();  // answered without waiting for 64 MiB
    ASSERT_TRUE(a);
    EXPECT_EQ(a->status, 413);
    EXPECT_EQ(a->header("Connection"), "close");
}

TEST(Connections, AmbiguousFramingIsRefusedAndTheConnectionClosed) {
    ServerProcess s;
    const std::string body = R"({"name":"x"})";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"two lengths", "POST /v1/maps HTTP/1.1\r\nHost: x\r\nContent-Length: 12\r\nContent-Length: 5\r\n\r\n" + body},
        {"length and chunked",
         "POST /v1/maps HTTP/1.1\r\nHost: x\r\nContent-Length: 12\r\nTransfer-Encoding: chunked\r\n\r\n" + body},
        {"signed length", "POST /v1/maps HTTP/1.1\r\nHost: x\r\nContent-Length: +12\r\n\r\n" + body},
        {"a GET with a body", "GET /v1/maps HTTP/1.1\r\nHost: x\r\nContent-Length: 12\r\n\r\n" + body},
        {"an unknown coding", "POST /v1/maps HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: gzip, chunked\r\n\r\n" + body},
        // Lines cpp-httplib's parser skips without a word: the length would go unseen.
        {"space before a colon", "GET /health HTTP/1.1\r\nHost: x\r\nContent-Length : 12\r\n\r\n" + body},
        {"a bare LF", "GET /health HTTP/1.1\r\nHost: x\r\nContent-Length: 12\n\r\n" + body},
        {"a folded line", "POST /v1/maps HTTP/1.1\r\nHost: x\r\nContent-Length: 12\r\n X: y\r\n\r\n" + body},
    };
    for (const auto& [what, request] : cases) {
        RawConnection c(s.port());
        ASSERT_TRUE(c.send(request + raw_get("/v1/maps/999")));
        const auto a = c.read_answer();
        ASSERT_TRUE(a) << what;
        EXPECT_TRUE(a->status == 400 || a->status == 411) << what << ": " << a->head;
        EXPECT_EQ(a->header("Connection"), "close") << what;
        EXPECT_FALSE(c.read_answer(1s)) << what << ": bytes after it were answered as a request";
    }
    EXPECT_EQ(map_count(s), 0);
}

TEST(Connections, PastTheConnectionCapClientsGetAQuick503) {
    ServerProcess s({"--max-connections", "4"});
    std::vector<std::unique_ptr<RawConnection>> held;
    for (int i = 0; i < 4; ++i) {
        held.push_back(std::make_unique<RawConnection>(s.port()));
        ASSERT_TRUE(held.back()->send(raw_get("/health")));
        ASSERT_TRUE(held.back()->read_answer());
    }
    RawConnection extra(s.port());
    ASSERT_TRUE(extra.connected());
    extra.send(raw_get("/health"));
    const auto busy = extra.read_answer(3s);
    ASSERT_TRUE(busy);
    EXPECT_EQ(busy->status, 503);
    EXPECT_EQ(busy->header("Retry-After"), "1");
    EXPECT_EQ(json::parse(busy->body).at("error").at("code"), "server_busy");

    held.pop_back();  // one closes: a new client is served again
    std::this_thread::sleep_for(200ms);
    RawConnection again(s.port());
    ASSERT_TRUE(again.send(raw_get("/health")));
    const auto ok = again.read_answer(3s);
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok->status, 200);
}

// A client trickling its head a byte at a time was kept forever by a per-read timeout.
TEST(Connections, ASlowHeadIsCutOffAtTheHeaderTimeout) {
    ServerProcess s({"--header-timeout", "1"});
    RawConnection c(s.port());
    const std::string head = "GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
    const auto start = std::chrono::steady_clock::now();
    bool cut = false;
    for (std::size_t i = 0; i < 40 && !cut; ++i) {
        if (!c.send(std::string(1, i < head.size() ? head[i] : 'a'))) cut = true;
        else cut = c.closed_within(150ms);
    }
    EXPECT_TRUE(cut) << "the trickling client was still connected after 6 s";
    EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
}

TEST(Connections, KeepAliveEndsAfterTheRequestCap) {
    ServerProcess s({"--keep-alive-requests", "3"});
    RawConnection c(s.port());
    ASSERT_TRUE(c.send(raw_get("/health") + raw_get("/health") + raw_get("/health") + raw_get("/health")));
    for (int i = 0; i < 3; ++i) {
        const auto a = c.read_answer();
        ASSERT_TRUE(a);
        EXPECT_EQ(a->status, 200);
        if (i == 2) {
            EXPECT_EQ(a->header("Connection"), "close");
        }
    }
    EXPECT_TRUE(c.closed_within(3s));
}

// `curl -d` sends JSON as application/x-www-form-urlencoded; cpp-httplib parsed such bodies as
// forms and refused them past 8 KiB.
TEST(Connections, AFormEncodedJsonBodyOver8KiBIsAccepted) {
    ServerProcess s;
    const std::string body = R"({"name":"big form",)" + std::string(12000, ' ') + R"("description":"spaced"})";
    const auto r = s.post_raw("/v1/maps", body, "application/x-www-form-urlencoded");
    EXPECT_EQ(r.status, 201) << r.raw;
    EXPECT_EQ(map_count(s), 1);
}

// cpp-httplib picks Brotli whenever a client lists it, at its slowest quality: a browser
// (which always lists br) waited 2 s for a 1,000-RP export that gzip sends in 15 ms.
TEST(Connections, ABrowserGetsGzipNotBrotli) {
    ServerProcess s;
    ASSERT_EQ(s.post("/v1/maps", json{{"name", "compressed"}}).status, 201);
    const struct {
        std::string accept, expected;
    } cases[] = {{"gzip, deflate, br", "gzip"}, {"br;q=1.0, gzip;q=0.8", "gzip"}, {"br", ""}, {"gzip", "gzip"}};
    for (const auto& c : cases) {
        RawConnection conn(s.port());
        ASSERT_TRUE(conn.send(raw_get("/v1/maps", "Accept-Encoding: " + c.accept + "\r\n")));
        const auto answer = conn.read_answer();
        ASSERT_TRUE(answer) << c.accept;
        EXPECT_EQ(answer->status, 200) << c.accept;
        EXPECT_EQ(answer->header("Content-Encoding"), c.expected) << c.accept;
    }
}

// cpp-httplib set SO_REUSEPORT, so a second server on the port started and the kernel split
// requests between two databases.
TEST(Connections, ASecondServerOnTheSamePortRefusesToStart) {
    ServerProcess first;
    const auto second = locus::testing::run_command({"/usr/bin/timeout", "10", LOCUS_SERVER_BIN, "--db", first.dir() + "/second.db", "--host",
                                                     "127.0.0.1", "--port", std::to_string(first.port())});
    EXPECT_NE(second.status, 0);
    EXPECT_NE(second.err.find("cannot listen on 127.0.0.1:" + std::to_string(first.port())), std::string::npos)
        << second.err;
    EXPECT_NE(second.err.find("in use"), std::string::npos) << second.err;
}

TEST(Connections, ShutdownDoesNotWaitForIdleConnections) {
    ServerProcess s({"--keep-alive-timeout", "60"});
    std::vector<std::unique_ptr<RawConnection>> idle;
    for (int i = 0; i < 8; ++i) {
        idle.push_back(std::make_unique<RawConnection>(s.port()));
        idle.back()->send(raw_get("/health"));
        ASSERT_TRUE(idle.back()->read_answer());
    }
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(s.stop(), 0);
    EXPECT_LT(std::chrono::steady_clock::now() - start, 10s) << "shutdown waited for the keep-alive timeout";
}

}  // namespace
}  // namespace server_connections_test
