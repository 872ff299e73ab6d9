// `locus bench thin` against the real server, on the tiny PUTMC fixture (tests/fixtures/putmc:
// one walk of 3 scans): tracks replaying it as thin clients get their scans fused and stored,
// the server's CPU is read from /proc, and what the command refuses.
#include <gtest/gtest.h>

#include <stdexcept>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace bench_thin_test {
namespace {

using locus::testing::run_command;
using locus::testing::ServerProcess;
using nlohmann::json;

const std::string kFixture = std::string(LOCUS_TEST_FIXTURES) + "/putmc";

std::string import_fixture(const ServerProcess& server) {
    const auto r = run_command({LOCUS_CLI_BIN, "import", "putmc", "--server", server.url(), "--map", "PUTMC", "--no-progress", kFixture});
    if (r.status != 0) throw std::runtime_error("import putmc: " + r.err);
    return std::to_string(json::parse(r.out).at("map_id").get<int>());
}

TEST(BenchThin, TracksReplayTheWalkAndTheServerFusesEveryScan) {
    ServerProcess server{{"--quiet"}};
    const std::string map = import_fixture(server);
    const auto r = run_command({LOCUS_CLI_BIN, "bench", "thin", kFixture, "--server", server.url(), "--map", map, "--tracks", "3", "--seconds", "3",
                                "--pid", std::to_string(server.pid())});
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    EXPECT_EQ(out["tracks"], 3);
    EXPECT_EQ(out["walks"], 1);
    EXPECT_EQ(out["errors"], 0) << out.dump();
    // Each track's first request (due at 0, 1.3 and 2.7 s) at least, each a scan fused.
    EXPECT_GE(out["requests"].get<int>(), 3);
    EXPECT_GE(out["fixes_stored"].get<int>(), out["requests"].get<int>());
    EXPECT_GT(out["p50_ms"].get<double>(), 0.0);
    EXPECT_GT(out["server_cpu_s"].get<double>(), 0.0);
    EXPECT_GT(out["server_rss_kb"]["after"].get<double>(), 0.0);
    // The tracks are closed at the end.
    const auto open = server.get("/v1/maps/" + map + "/positions");
    ASSERT_EQ(open.status, 200) << open.raw;
    EXPECT_TRUE(open.body["positions"].empty()) << open.raw;
}

TEST(BenchThin, RefusesWhatItCannotReplay) {
    ServerProcess server{{"--quiet"}};
    const std::string map = import_fixture(server);
    // A directory with no walk under it.
    auto r = run_command({LOCUS_CLI_BIN, "bench", "thin", kFixture + "/map", "--server", server.url(), "--map", map});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("holds no PUTMC walk"), std::string::npos) << r.err;
    // A map the server does not have: the first open's answer, named.
    r = run_command({LOCUS_CLI_BIN, "bench", "thin", kFixture, "--server", server.url(), "--map", "999"});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("opening track 0 answered 422"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("map 999 not found"), std::string::npos) << r.err;
    // Load tests stay on this machine.
    r = run_command({LOCUS_CLI_BIN, "bench", "thin", kFixture, "--server", "http://192.0.2.1:8080", "--map", map});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("loopback"), std::string::npos) << r.err;
    // A process id that is not running.
    r = run_command({LOCUS_CLI_BIN, "bench", "thin", kFixture, "--server", server.url(), "--map", map, "--pid", "999999999"});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("no such process"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace bench_thin_test
