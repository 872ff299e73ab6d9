// Mistakes in the server's flags are one clear line with what to do, before anything is
// created: an open host without an API key, a database whose directory is missing, a port in
// use.
#include <gtest/gtest.h>

#include <filesystem>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_startup_test {
namespace {

using locus::testing::run_command;
using locus::testing::ServerProcess;

// The server's last stderr line, which says why it stopped.
std::string last_line(const std::string& err) {
    const std::size_t end = err.find_last_not_of('\n');
    const std::size_t start = err.rfind('\n', end);
    return err.substr(start == std::string::npos ? 0 : start + 1, end - (start == std::string::npos ? 0 : start + 1) + 1);
}

TEST(Startup, AnOpenHostWithoutAKeyIsRefused) {
    const std::string dir = locus::testing::make_temp_dir();
    const auto r = run_command({"/usr/bin/timeout", "10", LOCUS_SERVER_BIN, "--db", dir + "/x.db", "--host", "0.0.0.0", "--port", "0"});
    EXPECT_EQ(r.status, 2) << r.err;
    const std::string line = last_line(r.err);
    EXPECT_NE(line.find("refusing to listen on 0.0.0.0 without an API key"), std::string::npos) << line;
    EXPECT_NE(line.find("--api-key"), std::string::npos) << line;
    EXPECT_NE(line.find("--allow-open-writes"), std::string::npos) << line;
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.db")) << "nothing may be created before the flags are checked";
    std::filesystem::remove_all(dir);
}

TEST(Startup, AMissingDatabaseDirectoryIsNamed) {
    const std::string dir = locus::testing::make_temp_dir();
    const auto r = run_command({"/usr/bin/timeout", "10", LOCUS_SERVER_BIN, "--db", dir + "/no/such/dir/locus.db", "--port", "0"});
    EXPECT_EQ(r.status, 2) << r.err;
    const std::string line = last_line(r.err);
    EXPECT_NE(line.find("its directory '" + dir + "/no/such/dir' does not exist"), std::string::npos) << line;
    EXPECT_NE(line.find("mkdir -p " + dir + "/no/such/dir"), std::string::npos) << line;
    EXPECT_FALSE(std::filesystem::exists(dir + "/no")) << "the server must not create directories it was not asked for";
    std::filesystem::remove_all(dir);
}

TEST(Startup, APortInUseSaysWhatToDo) {
    ServerProcess first;
    const auto second = run_command({"/usr/bin/timeout", "10", LOCUS_SERVER_BIN, "--db", first.dir() + "/second.db", "--port",
                                     std::to_string(first.port())});
    EXPECT_EQ(second.status, 1) << second.err;
    const std::string line = last_line(second.err);
    EXPECT_NE(line.find("Address already in use"), std::string::npos) << line;
    EXPECT_NE(line.find("another --port"), std::string::npos) << line;
    EXPECT_EQ(first.get("/health").status, 200);
}

}  // namespace
}  // namespace server_startup_test
