// GET /v1/radiomaps/{id}/export's limits against the real server: at most --max-exports at
// once (the next one is 503 server_busy before any byte of the body), the slot held until the
// answer ends or its client goes away, and an export still being written at --export-timeout
// cut without its last chunk, its slot given back.
//
// A client that stops reading holds an export open only once the server's writes block: the
// radio map is made larger than the loopback socket buffers can take (the server's send
// buffer grows to tcp_wmem's maximum; the client's receive buffer is set small), so the
// export is still being written when the test looks, with no timing involved.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <thread>

#include "hierarchy.hpp"
#include "raw_connection.hpp"
#include "server_process.hpp"
#include "test_database.hpp"
#include "build_paths.hpp"

namespace server_export_limits_test {
namespace {

using locus::testing::RawConnection;
using locus::testing::ServerProcess;
using locus::testing::body_of;
using locus::testing::raw_get;
using nlohmann::json;
using namespace std::chrono_literals;

constexpr int kStalledReceiveBuffer = 64 * 1024;  // small, yet read back fast once the test reads

// The most a socket's send buffer grows to (tcp_wmem's third value), or 4 MiB if unreadable.
long long send_buffer_max() {
    std::ifstream in("/proc/sys/net/ipv4/tcp_wmem");
    long long lo = 0, start = 0, max = 0;
    if (in >> lo >> start >> max && max > 0) return max;
    return 4LL << 20;
}

std::string export_path(std::int64_t radiomap) { return "/v1/radiomaps/" + std::to_string(radiomap) + "/export"; }

// A radio map whose export is well past what the socket buffers between the server and a
// stalled client hold; returns its id and its RP count. Its RPs' names are mostly a control
// character, which JSON writes as six bytes (\u0001): fewer rows for the bytes (PostgreSQL
// imports about 3,000 rows a second).
std::pair<std::int64_t, std::size_t> big_radiomap(const ServerProcess& s, std::int64_t floor) {
    constexpr long long kBytesPerRp = 1200;  // exported; a little under what it is
    const auto rps_wanted = static_cast<std::size_t>((send_buffer_max() + (2LL << 20)) / kBytesPerRp + 1);
    json rps = json::array();
    for (std::size_t i = 0; i < rps_wanted; ++i)
        rps.push_back({{"name", std::to_string(i) + std::string(190, '\x01')},
                       {"x", static_cast<double>(i % 50)},
                       {"y", static_cast<double>(i / 50 % 50)},
                       {"scans", 7}});
    const auto imported = body_of(s.post("/v1/floors/" + std::to_string(floor) + "/radiomaps/import", {{"name", "big"}, {"rps", rps}}), 201);
    return {imported.at("id").get<std::int64_t>(), rps_wanted};
}

// An export whose client read the answer's head and then stopped reading.
std::unique_ptr<RawConnection> stalled_export(const ServerProcess& s, std::int64_t radiomap) {
    auto c = std::make_unique<RawConnection>(s.port(), kStalledReceiveBuffer);
    EXPECT_TRUE(c->connected());
    EXPECT_TRUE(c->send(raw_get(export_path(radiomap))));
    const auto head = c->read_answer(10s);  // a chunked answer: its body stays unread
    EXPECT_TRUE(head);
    if (head) {
        EXPECT_EQ(head->status, 200) << head->head;
        EXPECT_EQ(head->header("Transfer-Encoding"), "chunked") << head->head;
    }
    return c;
}

// The first answer to GET `path` that is not 503 within `within` (503s retried): the slot
// comes back when the server notices, not at a known instant.
locus::testing::Response first_not_busy(const ServerProcess& s, const std::string& path, std::chrono::milliseconds within) {
    const auto until = std::chrono::steady_clock::now() + within;
    for (;;) {
        auto r = s.get(path);
        if (r.status != 503 || std::chrono::steady_clock::now() >= until) return r;
        std::this_thread::sleep_for(50ms);
    }
}

std::vector<std::string> server_args(std::initializer_list<std::string> more) {
    std::vector<std::string> args{"--quiet", "--max-body-bytes", std::to_string(64 << 20)};
    args.insert(args.end(), more);
    return args;
}

TEST(ServerExportLimits, PastTheCapAnExportIsBusyUntilTheHeldOneIsLetGo) {
    ServerProcess s(server_args({"--max-exports", "1"}));
    const auto h = locus::testing::make_hierarchy(s);
    const auto [big, rp_count] = big_radiomap(s, h.floor);

    auto held = stalled_export(s, big);
    // Its head was written, so its slot is taken; its body cannot all fit in the buffers.
    RawConnection second(s.port());
    ASSERT_TRUE(second.send(raw_get(export_path(big))));
    const auto busy = second.read_answer(10s);
    ASSERT_TRUE(busy);
    EXPECT_EQ(busy->status, 503) << busy->head;
    EXPECT_EQ(busy->header("Retry-After"), "5") << busy->head;
    const auto error = json::parse(busy->body);
    EXPECT_EQ(error.at("error").at("code"), "server_busy") << busy->body;
    EXPECT_NE(error.at("error").at("message").get<std::string>().find("--max-exports"), std::string::npos) << busy->body;
    // Busy is decided before the radio map is looked up: an unknown one is 503 too, not 404.
    EXPECT_EQ(s.get(export_path(big + 1000)).status, 503);
    // Other reads are not held up by it.
    EXPECT_EQ(s.get("/v1/radiomaps/" + std::to_string(big)).status, 200);

    // The client goes away mid-stream: its slot comes back long before the 10 s write timeout
    // would have ended the answer.
    held.reset();
    const auto again = first_not_busy(s, export_path(big), 5s);
    ASSERT_EQ(again.status, 200) << again.raw.substr(0, 300);
    EXPECT_EQ(again.body.at("rps").size(), rp_count);
    // Finished exports hold no slot either.
    EXPECT_EQ(s.get(export_path(big)).status, 200);
}

TEST(ServerExportLimits, AnExportPastItsTimeIsCutWithoutItsLastChunk) {
    ServerProcess s(server_args({"--max-exports", "1", "--export-timeout", "1"}));
    const auto h = locus::testing::make_hierarchy(s);
    const auto big = big_radiomap(s, h.floor).first;
    locus::testing::make_rp(s, h.radiomap, "small", 1, 1);  // a later export that finishes well inside a second

    const auto started = std::chrono::steady_clock::now();
    auto stalled = stalled_export(s, big);
    // The client reads nothing more until the server says it cut the export.
    while (s.log().find("\"event\":\"export_timeout\"") == std::string::npos && std::chrono::steady_clock::now() - started < 10s)
        std::this_thread::sleep_for(50ms);
    ASSERT_NE(s.log().find("\"event\":\"export_timeout\""), std::string::npos) << s.log();
    // Cut at its deadline, not a 10 s write timeout later.
    EXPECT_LT(std::chrono::steady_clock::now() - started, 6s);
    ASSERT_TRUE(stalled->closed_within(10s)) << "the server did not close the connection";
    // What arrived is a chunked body without its terminating chunk: a client can tell it is short.
    const std::string& body = stalled->pending();
    EXPECT_GT(body.size(), 0u);
    EXPECT_FALSE(body.ends_with("\r\n0\r\n\r\n")) << body.substr(body.size() > 100 ? body.size() - 100 : 0);
    EXPECT_EQ(body.find("HTTP/1.1"), std::string::npos) << "nothing is written after the cut";

    const auto later = first_not_busy(s, export_path(h.radiomap), 5s);
    ASSERT_EQ(later.status, 200) << later.raw;
    EXPECT_EQ(later.body.at("rps").size(), 1u);
}

TEST(ServerExportLimits, BadLimitsAreRefusedAtStart) {
    const std::string dir = locus::testing::make_temp_dir();
    const std::pair<const char*, const char*> cases[] = {
        {"--max-exports", "0"}, {"--max-exports", "-1"}, {"--max-exports", "abc"}, {"--export-timeout", "0"}, {"--export-timeout", "x"}};
    for (const auto& [option, value] : cases) {
        // `timeout`: a server that wrongly started is stopped rather than hanging the test.
        const auto r = locus::testing::run_command(
            {"/usr/bin/timeout", "10", LOCUS_SERVER_BIN, "--db", dir + "/never.db", "--port", "0", option, value});
        EXPECT_NE(r.status, 0) << option << " " << value;
        EXPECT_NE(r.status, 124) << option << " " << value << ": the server started";
        EXPECT_NE(r.err.find(option), std::string::npos) << option << " " << value << ": " << r.err;
    }
}

// A failure part way (here: PostgreSQL ends the export's own connection while its client has
// stopped reading) ends the answer the same way: no terminating chunk, export_failed logged,
// the slot given back, and the server serving on.
TEST(ServerExportLimits, AnExportFailingPartWayIsCutWithoutItsLastChunk) {
    if (!locus::testing::on_postgres()) GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)";
    ServerProcess s(server_args({"--max-exports", "1"}));
    const auto h = locus::testing::make_hierarchy(s);
    const auto big = big_radiomap(s, h.floor).first;
    locus::testing::make_rp(s, h.radiomap, "small", 1, 1);

    auto stalled = stalled_export(s, big);
    // The export's connection is the one whose last statement read a page of RPs (it may be
    // between pages still, so PostgreSQL looks for it until it is there, for at most 5 s).
    const std::string database = s.db().substr(s.db().rfind('/') + 1);
    locus::testing::cluster_exec(
        "DO $$ BEGIN FOR i IN 1..100 LOOP "
        "IF (SELECT count(pg_terminate_backend(pid)) FROM pg_stat_activity WHERE datname = '" + database +
        "' AND (query LIKE '%FROM rps WHERE radiomap_id + 0%' OR query LIKE '%FROM measurements WHERE rp_id BETWEEN%')) > 0 "
        "THEN RETURN; END IF; PERFORM pg_sleep(0.05); END LOOP; RAISE EXCEPTION 'no export connection'; END $$");
    ASSERT_TRUE(stalled->closed_within(10s)) << "the server did not end the export";
    const std::string& body = stalled->pending();
    EXPECT_FALSE(body.ends_with("\r\n0\r\n\r\n")) << body.substr(body.size() > 100 ? body.size() - 100 : 0);
    EXPECT_EQ(body.find("HTTP/1.1"), std::string::npos) << "nothing is written after the cut";
    EXPECT_NE(s.log().find("\"event\":\"export_failed\""), std::string::npos) << s.log();

    const auto later = first_not_busy(s, export_path(h.radiomap), 5s);
    ASSERT_EQ(later.status, 200) << later.raw;
    EXPECT_EQ(later.body.at("rps").size(), 1u);
}

}  // namespace
}  // namespace server_export_limits_test
