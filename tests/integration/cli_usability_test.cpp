// What a new user meets on the `locus` command line (docs/survey.md, README): a misspelled option
// is named, help reads plainly, messages name the real problem (no such radio map, no server,
// a walk that matches nothing), imports say which radio map is which, `export -o` reports what
// it wrote, and the example files the docs use exist and work.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "server_process.hpp"
#include "text_file.hpp"
#include "build_paths.hpp"

namespace cli_usability_test {
namespace {

using locus::testing::make_temp_dir;
using locus::testing::run_command;
using locus::testing::ServerProcess;
using nlohmann::json;

using locus::testing::slurp;
using locus::testing::contains;

const std::string kSource = LOCUS_SOURCE_DIR;
const std::string kFixtures = LOCUS_TEST_FIXTURES;

// A loopback port nobody listens on: bound, then released.
int closed_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    ::close(fd);
    return ntohs(a.sin_port);
}

TEST(CliOptions, AMisspelledOptionIsNamedNotTakenForAFile) {
    // "--sever URL FILE" used to put URL into FILE: "File does not exist: http://...".
    const auto r = run_command({LOCUS_CLI_BIN, "import", "uji", "--sever", "http://127.0.0.1:1", kFixtures + "/uji_tiny.csv"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "unknown option '--sever' for 'locus import uji'")) << r.err;
    EXPECT_TRUE(contains(r.err, "did you mean '--server'?")) << r.err;
    EXPECT_FALSE(contains(r.err, "File does not exist")) << r.err;

    const auto e = run_command({LOCUS_CLI_BIN, "export", "--radiomap", "1", "--formt=csv"});
    EXPECT_NE(e.status, 0);
    EXPECT_TRUE(contains(e.err, "unknown option '--formt' for 'locus export'; did you mean '--format'?")) << e.err;
}

TEST(CliOptions, HelpShowsNoProgressAsAPlainFlag) {
    for (const std::vector<std::string>& cmd : {std::vector<std::string>{"import", "uji"}, {"import", "anyplace"},
                                               {"import", "find3"}, {"survey", "upload"}}) {
        std::vector<std::string> argv{LOCUS_CLI_BIN};
        argv.insert(argv.end(), cmd.begin(), cmd.end());
        argv.push_back("--help");
        const auto r = run_command(argv);
        EXPECT_EQ(r.status, 0);
        EXPECT_TRUE(contains(r.out, "--no-progress")) << r.out;
        EXPECT_FALSE(contains(r.out, "{false}")) << r.out;
    }
}

TEST(CliMessages, RssOutOfRangeIsPrintedPlainly) {
    const std::string dir = make_temp_dir();
    std::ofstream(dir + "/bad.jsonl") << R"({"rp": "A", "x": 1, "y": 1, "readings": [{"bssid": "aa:bb:cc:00:00:01", "rss": 50}]})"
                                      << "\n";
    ServerProcess server{{"--quiet", "--demo"}};
    const auto r = run_command({LOCUS_CLI_BIN, "survey", "upload", "--server", server.url(), "--radiomap", "1", "--no-progress",
                                dir + "/bad.jsonl"});
    EXPECT_TRUE(contains(r.err, "'rss' = 50 dBm is outside [-120, 0]")) << r.err;
    std::filesystem::remove_all(dir);
}

TEST(CliMessages, AServerThatIsDownIsNamed) {
    const std::string url = "http://127.0.0.1:" + std::to_string(closed_port());
    const auto r = run_command({LOCUS_CLI_BIN, "export", "--server", url, "--radiomap", "1", "--retries", "2"});
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(contains(r.err, "cannot connect to " + url + " (connection refused) after 2 attempts; is locus-server running?"))
        << r.err;

    const auto b = run_command({LOCUS_CLI_BIN, "bench", "localize", "--server", url, "--radiomap", "1", "--retries", "2"});
    EXPECT_EQ(b.status, 1);
    EXPECT_TRUE(contains(b.err, "cannot connect to " + url + " (connection refused) after 2 attempts; is locus-server running?"))
        << b.err;
}

TEST(CliMessages, BenchOnAMissingRadioMapSaysItDoesNotExist) {
    ServerProcess server{{"--quiet", "--demo"}};
    const auto r = run_command({LOCUS_CLI_BIN, "bench", "localize", "--server", server.url(), "--radiomap", "999", "--requests", "10"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "radio map 999 does not exist")) << r.err;
    EXPECT_FALSE(contains(r.err, "cannot export")) << r.err;
}

TEST(CliMessages, ReplayAgainstARadioMapSharingNoApFails) {
    // The simulator's walk hears 02:10:... APs; the demo radio map has 00:1a:2b:... only.
    const std::string dir = make_temp_dir();
    const std::string walk = dir + "/walk.jsonl";
    ASSERT_EQ(run_command({LOCUS_CLI_BIN, "sim", "--scenario", "basement", "--seed", "3", "--out", walk}).status, 0);
    ServerProcess server{{"--quiet", "--demo"}};
    const auto r = run_command({LOCUS_CLI_BIN, "replay", "--server", server.url(), "--radiomap", "1", "--rule", "all", walk});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "no scan of " + walk + " matched any AP of radio map 1")) << r.err;
    std::filesystem::remove_all(dir);
}

TEST(CliExport, WritingAFilePrintsWhatWentIntoIt) {
    ServerProcess server{{"--quiet", "--demo"}};
    const std::string dir = make_temp_dir();
    const std::string file = dir + "/rm1.json";
    const auto r = run_command({LOCUS_CLI_BIN, "export", "--server", server.url(), "--radiomap", "1", "-o", file});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out, "");  // the data is in the file
    const json doc = json::parse(slurp(file));
    std::size_t measurements = 0;
    for (const auto& rp : doc["rps"]) measurements += rp["measurements"].size();
    EXPECT_EQ(r.err, "wrote radio map 1: " + std::to_string(doc["rps"].size()) + " RPs, " + std::to_string(measurements) +
                         " measurements to " + file + "\n");
    std::filesystem::remove_all(dir);
}

TEST(CliImport, UjiNamesItsRadioMapsByBuildingAndFloorAndPrintsTheirIds) {
    ServerProcess server{{"--quiet"}};
    const auto r = run_command({LOCUS_CLI_BIN, "import", "uji", "--server", server.url(), "--no-progress", kFixtures + "/uji_tiny.csv"});
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    ASSERT_EQ(out["radiomap_list"].size(), out["radiomaps"].get<std::size_t>());
    for (const auto& rm : out["radiomap_list"]) {
        const json stored = server.get("/v1/radiomaps/" + std::to_string(rm["id"].get<int>())).body;
        EXPECT_EQ(stored["name"], rm["name"]);
        EXPECT_EQ(stored["floor_id"], rm["floor_id"]);
        const std::string b = rm["building"].get<std::string>().substr(std::string("Building ").size());
        const std::string f = rm["floor"].get<std::string>().substr(std::string("Floor ").size());
        EXPECT_EQ(rm["name"], "UJIIndoorLoc building " + b + " floor " + f);
        EXPECT_TRUE(contains(r.err, "radio map " + std::to_string(rm["id"].get<int>()) + " '" + rm["name"].get<std::string>() +
                                        "': " + rm["building"].get<std::string>() + " / " + rm["floor"].get<std::string>()))
            << r.err;
    }
}

TEST(CliDocs, SurveyExampleFilesUpload) {
    // docs/survey.md uploads docs/examples/walk1.jsonl and walk2.csv.
    ServerProcess server{{"--quiet", "--demo"}};
    const auto r = run_command({LOCUS_CLI_BIN, "survey", "upload", "--server", server.url(), "--radiomap", "1", "--no-progress",
                                kSource + "/docs/examples/walk1.jsonl", kSource + "/docs/examples/walk2.csv"});
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    EXPECT_EQ(out["malformed_lines"], 0);
    EXPECT_EQ(out["failed"], 0);
    EXPECT_GT(out["readings"].get<int>(), 0);
}

TEST(CliDocs, PdrTrackSampleLogGivesATrack) {
    // docs/pdr.md runs `pdr track` on docs/examples/imu_walk.csv (20 s of a real Oxford walk,
    // 35 steps by its foot switches).
    const auto r = run_command({LOCUS_CLI_BIN, "pdr", "track", kSource + "/docs/examples/imu_walk.csv"});
    ASSERT_EQ(r.status, 0) << r.err;
    std::istringstream lines(r.out);
    std::string line;
    std::getline(lines, line);
    EXPECT_EQ(line.rfind("t,x,y,", 0), 0u) << line;
    int rows = 0;
    while (std::getline(lines, line)) ++rows;
    EXPECT_GE(rows, 20);
    EXPECT_LE(rows, 40);
}

}  // namespace
}  // namespace cli_usability_test
