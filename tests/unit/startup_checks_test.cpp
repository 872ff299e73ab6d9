// The server's start-up checks (server/startup/checks.hpp).
#include "startup/checks.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "temp_dir.hpp"

namespace startup_checks_test {
namespace {

using namespace locus::startup;

TEST(StartupChecks, LoopbackHosts) {
    for (const char* h : {"127.0.0.1", "127.0.0.2", "127.255.0.1", "localhost", "::1", "[::1]"}) EXPECT_TRUE(is_loopback_host(h)) << h;
    for (const char* h : {"0.0.0.0", "::", "192.168.1.10", "10.0.0.1", "example.org", "1270.0.0.1"})
        EXPECT_FALSE(is_loopback_host(h)) << h;
}

TEST(StartupChecks, OpenWritesNeedAKeyOrToBeAskedFor) {
    EXPECT_FALSE(open_writes_problem("127.0.0.1", false, false));
    EXPECT_FALSE(open_writes_problem("0.0.0.0", true, false));
    EXPECT_FALSE(open_writes_problem("0.0.0.0", false, true));
    const auto problem = open_writes_problem("0.0.0.0", false, false);
    ASSERT_TRUE(problem);
    EXPECT_NE(problem->find("--allow-open-writes"), std::string::npos);
}

TEST(StartupChecks, TheDatabaseDirectoryMustExist) {
    locus::testing::TempDir tmp("startup");
    EXPECT_FALSE(database_path_problem(tmp.file("locus.db")));
    EXPECT_FALSE(database_path_problem("sqlite:" + tmp.file("locus.db")));
    EXPECT_FALSE(database_path_problem("locus.db"));  // the working directory
    EXPECT_FALSE(database_path_problem("postgresql://locus@db/locus"));
    const auto missing = database_path_problem(tmp.file("a/b/locus.db"));
    ASSERT_TRUE(missing);
    EXPECT_NE(missing->find("mkdir -p " + tmp.file("a/b")), std::string::npos) << *missing;
    std::ofstream(tmp.file("plain-file")) << "x";
    const auto not_dir = database_path_problem(tmp.file("plain-file") + "/x.db");
    ASSERT_TRUE(not_dir);
    EXPECT_NE(not_dir->find("is not a directory"), std::string::npos) << *not_dir;
}

}  // namespace
}  // namespace startup_checks_test
