// `locus bench map-memory` (docs/deploy.md, memory per replica) on a small floor: it builds the
// radio map it says it built, reads the server's memory, localizes where the query was taken,
// and measures an existing radio map on a restarted server; a wrong --pid is named.
#include <gtest/gtest.h>

#include "server_process.hpp"
#include "text_file.hpp"
#include "build_paths.hpp"

namespace bench_map_memory_test {
namespace {

using locus::testing::contains;
using locus::testing::run_command;
using locus::testing::ServerProcess;
using nlohmann::json;

TEST(BenchMapMemory, BuildsTheRadioMapAndReadsTheServersMemory) {
    ServerProcess server{{"--quiet"}};
    const int pid = static_cast<int>(server.pid());
    ASSERT_GT(pid, 0);
    const auto r = run_command({LOCUS_CLI_BIN, "bench", "map-memory", "--server", server.url(), "--pid", std::to_string(pid),
                                "--width", "40", "--height", "20", "--ap-spacing", "10"});
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    EXPECT_EQ(out.at("rps"), 800);  // one RP per 1 m cell
    EXPECT_EQ(out.at("transmitters"), 8);
    EXPECT_GT(out.at("measurements").get<int>(), 800);
    EXPECT_GT(out.at("rss_mb").at("before").get<double>(), 1.0);
    EXPECT_GE(out.at("peak_rss_mb").get<double>(), out.at("rss_mb").at("after_index").get<double>());
    // The query was modelled at the floor's centre: the answer is near it.
    EXPECT_NEAR(out.at("answer").at("x").get<double>(), 20.0, 3.0);
    EXPECT_NEAR(out.at("answer").at("y").get<double>(), 10.0, 3.0);

    // A replica started on the same data: the map is measured, not built again.
    server.stop();
    server.start();
    const int again = static_cast<int>(server.pid());
    const auto m = run_command({LOCUS_CLI_BIN, "bench", "map-memory", "--server", server.url(), "--pid", std::to_string(again),
                                "--radiomap", std::to_string(out.at("radiomap").get<int>())});
    ASSERT_EQ(m.status, 0) << m.err;
    const json existing = json::parse(m.out);
    EXPECT_EQ(existing.at("rps"), 800);
    EXPECT_EQ(existing.at("transmitters"), 8);
    EXPECT_NEAR(existing.at("answer").at("x").get<double>(), 20.0, 3.0);
}

TEST(BenchMapMemory, AProcessThatIsNotThereIsNamed) {
    ServerProcess server{{"--quiet"}};
    const auto r = run_command({LOCUS_CLI_BIN, "bench", "map-memory", "--server", server.url(), "--pid", "999999999"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "cannot read /proc/999999999/status")) << r.err;
}

}  // namespace
}  // namespace bench_map_memory_test
