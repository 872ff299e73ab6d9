// `locus backup` (docs/deploy.md, Backups): a copy taken while uploads go on holds every upload
// acknowledged before it started and a server started on it serves it; a copy of a quiet server
// serves the same export; bad input is refused with a clear message, exit non-zero, and nothing
// (not even a temp file) left behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "test_database.hpp"
#include "text_file.hpp"
#include "build_paths.hpp"

namespace cli_backup_test {
namespace {

using locus::testing::body_of;
using locus::testing::contains;
using locus::testing::make_temp_dir;
using locus::testing::run_command;
using locus::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;

json one_scan(int i) {
    return json::array({json::array({{{"type", "wifi"}, {"bssid", "aa:bb:cc:00:00:01"}, {"rss", -40 - i % 50}}})});
}

std::string export_path(std::int64_t radiomap) { return "/v1/radiomaps/" + std::to_string(radiomap) + "/export"; }

// A server on a copy of a database: its own temp dir, the copy put in place of its file.
void serve_copy(ServerProcess& server, const std::string& copy) {
    server.stop();
    for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(server.db_path() + suffix);
    fs::copy_file(copy, server.db_path());
    server.start();
}

// Files in dir, by name.
std::vector<std::string> names_in(const std::string& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

TEST(Backup, ACopyTakenDuringUploadsHoldsEveryUploadAcknowledgedBeforeIt) {
    if (locus::testing::on_postgres()) GTEST_SKIP() << "locus backup copies a SQLite file (pg_dump is PostgreSQL's tool)";
    ServerProcess server{{"--quiet"}};
    const auto h = locus::testing::make_hierarchy(server);
    const auto rp = locus::testing::make_rp(server, h.radiomap, "rp-1", 1.0, 2.0);
    const std::string scans = "/v1/rps/" + std::to_string(rp) + "/scans";

    std::atomic<int> acknowledged{0};
    std::atomic<bool> stop{false};
    std::thread uploader([&] {
        for (int i = 0; !stop; ++i) {
            // append, not "u" + std::to_string(i): GCC 12 warns falsely (-Wrestrict) on the latter.
            const auto r = server.post(scans, {{"upload_id", std::string("u").append(std::to_string(i))}, {"scans", one_scan(i)}});
            if (r.status != 200) break;
            ++acknowledged;
        }
    });
    while (acknowledged < 50) std::this_thread::sleep_for(std::chrono::milliseconds(5));

    const std::string dir = make_temp_dir();
    const int before = acknowledged;
    const auto r = run_command({LOCUS_CLI_BIN, "backup", "--db", server.db_path(), "--out", dir + "/copy.db"});
    const int after = acknowledged;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // uploads go on after the copy
    stop = true;
    uploader.join();
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "integrity check ok")) << r.out;
    EXPECT_GT(acknowledged.load(), after) << "the uploads were not still going on";

    ServerProcess restored{{"--quiet"}};
    serve_copy(restored, dir + "/copy.db");
    const auto copied = body_of(restored.get("/v1/rps/" + std::to_string(rp)));
    // One scan per upload: the copy has every upload acknowledged before the backup started,
    // and none that was not acknowledged by the time it ended.
    EXPECT_GE(copied.at("scans").get<int>(), before);
    EXPECT_LE(copied.at("scans").get<int>(), after + 1);  // +1: in flight, committed, not yet counted
    // One commit's state, not a torn copy: the AP's sample count moved with the RP's scan count.
    ASSERT_EQ(copied.at("measurements").size(), 1u);
    EXPECT_EQ(copied.at("measurements")[0].at("count"), copied.at("scans"));
    // The upload ids came along: sending the first one again changes nothing on the copy.
    const auto again = body_of(restored.post(scans, {{"upload_id", "u0"}, {"scans", one_scan(0)}}));
    EXPECT_FALSE(again.at("applied").get<bool>());
    // The copy is a working database: it takes new uploads.
    EXPECT_TRUE(body_of(restored.post(scans, {{"upload_id", "after-restore"}, {"scans", one_scan(1)}})).at("applied").get<bool>());
    fs::remove_all(dir);
}

TEST(Backup, ACopyOfAQuietServerServesTheSameExport) {
    if (locus::testing::on_postgres()) GTEST_SKIP() << "locus backup copies a SQLite file (pg_dump is PostgreSQL's tool)";
    ServerProcess server{{"--quiet", "--demo"}};
    const auto original = body_of(server.get(export_path(1)));
    ASSERT_FALSE(original.at("rps").empty());
    const std::string dir = make_temp_dir();
    ASSERT_EQ(run_command({LOCUS_CLI_BIN, "backup", "--db", "sqlite:" + server.db_path(), "--out", dir + "/copy.db"}).status, 0);
    // The copy is one self-contained file: no journal beside it.
    EXPECT_EQ(names_in(dir), std::vector<std::string>{"copy.db"});

    ServerProcess restored{{"--quiet"}};
    serve_copy(restored, dir + "/copy.db");
    EXPECT_EQ(body_of(restored.get(export_path(1))), original);
    fs::remove_all(dir);
}

TEST(Backup, AnExistingFileIsReplacedOnlyWithForce) {
    if (locus::testing::on_postgres()) GTEST_SKIP() << "locus backup copies a SQLite file (pg_dump is PostgreSQL's tool)";
    ServerProcess server{{"--quiet", "--demo"}};
    const std::string dir = make_temp_dir();
    const std::string out = dir + "/copy.db";
    std::ofstream(out) << "keep me";
    const auto refused = run_command({LOCUS_CLI_BIN, "backup", "--db", server.db_path(), "--out", out});
    EXPECT_NE(refused.status, 0);
    EXPECT_TRUE(contains(refused.err, "already exists; pass --force")) << refused.err;
    EXPECT_EQ(locus::testing::slurp(out), "keep me");
    EXPECT_EQ(names_in(dir), std::vector<std::string>{"copy.db"});

    const auto forced = run_command({LOCUS_CLI_BIN, "backup", "--db", server.db_path(), "--out", out, "--force"});
    EXPECT_EQ(forced.status, 0) << forced.err;
    EXPECT_NE(locus::testing::slurp(out), "keep me");
    EXPECT_EQ(names_in(dir), std::vector<std::string>{"copy.db"});
    fs::remove_all(dir);
}

TEST(Backup, BadInputIsNamedAndLeavesNothingBehind) {
    if (locus::testing::on_postgres()) GTEST_SKIP() << "locus backup copies a SQLite file (pg_dump is PostgreSQL's tool)";
    const std::string dir = make_temp_dir();
    const std::string out = dir + "/copy.db";

    const auto missing = run_command({LOCUS_CLI_BIN, "backup", "--db", dir + "/nope.db", "--out", out});
    EXPECT_EQ(missing.status, 1);
    EXPECT_TRUE(contains(missing.err, "no database file at '" + dir + "/nope.db'")) << missing.err;

    std::ofstream(dir + "/junk.db") << "this is not a database, just text long enough to be read as a header......";
    const auto junk = run_command({LOCUS_CLI_BIN, "backup", "--db", dir + "/junk.db", "--out", out});
    EXPECT_EQ(junk.status, 1);
    EXPECT_TRUE(contains(junk.err, "is not a Locus database")) << junk.err;

    ServerProcess server{{"--quiet"}};
    const auto no_dir = run_command({LOCUS_CLI_BIN, "backup", "--db", server.db_path(), "--out", dir + "/no/such/dir/copy.db"});
    EXPECT_EQ(no_dir.status, 1);
    EXPECT_TRUE(contains(no_dir.err, "directory '" + dir + "/no/such/dir' does not exist")) << no_dir.err;

    const auto itself = run_command({LOCUS_CLI_BIN, "backup", "--db", server.db_path(), "--out", server.db_path(), "--force"});
    EXPECT_EQ(itself.status, 1);
    EXPECT_TRUE(contains(itself.err, "is the database itself")) << itself.err;
    EXPECT_EQ(body_of(server.get("/health")).at("status"), "ok");  // the running server was not disturbed

    const auto pg = run_command({LOCUS_CLI_BIN, "backup", "--db", "postgresql://locus@db.example/locus", "--out", out});
    EXPECT_EQ(pg.status, 2);
    EXPECT_TRUE(contains(pg.err, "pg_dump")) << pg.err;

    EXPECT_EQ(names_in(dir), std::vector<std::string>{"junk.db"});
    fs::remove_all(dir);
}

}  // namespace
}  // namespace cli_backup_test
