// Storage faults (README, `/ready`): a database the server cannot write is a 503
// storage_unavailable that a client may retry, /ready says so while /health stays a cheap
// liveness check, nothing partial is written, and a database that cannot be opened stops the
// server at start-up with its path in the log.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_storage_test {
namespace {

using locus::testing::FileSizeLimit;
using locus::testing::Response;
using locus::testing::ServerProcess;
using nlohmann::json;

void expect_unavailable(const Response& r, const std::string& context) {
    EXPECT_EQ(r.status, 503) << context << ": " << r.raw;
    ASSERT_TRUE(r.body.is_object() && r.body.contains("error")) << context << ": " << r.raw;
    EXPECT_EQ(r.body["error"]["code"], "storage_unavailable") << context << ": " << r.raw;
    EXPECT_TRUE(r.body["error"]["message"].is_string()) << context;
}

// A radio map of `rps` RPs with `aps` aggregates each: a few hundred kB per import.
json radiomap_doc(const std::string& name, int rps, int aps) {
    json doc = {{"format", "locus-radiomap/1"}, {"name", name}, {"description", std::string(200, 'd')}, {"rps", json::array()}};
    for (int i = 0; i < rps; ++i) {
        json ms = json::array();
        for (int a = 0; a < aps; ++a) {
            char bssid[32];
            std::snprintf(bssid, sizeof bssid, "00:1a:2b:%02x:%02x:%02x", i / 256, i % 256, a);
            ms.push_back({{"type", "wifi"}, {"bssid", bssid}, {"mean", -60.0 - a % 30}, {"variance", 4.0}, {"count", 3}});
        }
        doc["rps"].push_back({{"name", "rp-" + std::to_string(i)}, {"x", i % 30}, {"y", i / 30}, {"scans", 3}, {"measurements", ms}});
    }
    return doc;
}

const std::string kServer = LOCUS_SERVER_BIN;

// Runs the server on `db` and expects it to stop at once: non-zero, its path in the log.
void expect_refused_at_start(const std::string& db, const std::string& what) {
    // timeout: a server that starts serving instead would otherwise hang the test.
    const auto r = locus::testing::run_command({"/usr/bin/timeout", "20", kServer, "--db", db, "--port", "0"});
    EXPECT_NE(r.status, 0) << what << ": " << r.err;
    EXPECT_NE(r.status, 124) << what << ": the server started serving: " << r.err;
    EXPECT_NE(r.err.find(db), std::string::npos) << what << ": the log does not name " << db << ":\n" << r.err;
    EXPECT_NE(r.err.find("\"event\":\"error\""), std::string::npos) << what << ": " << r.err;
}

TEST(ServerStorage, ReadyWritesAndHealthDoesNot) {
    ServerProcess s{{"--quiet"}};
    const auto ready = s.get("/ready");
    ASSERT_EQ(ready.status, 200) << ready.raw;
    EXPECT_EQ(ready.body, json({{"status", "ready"}}));
    EXPECT_EQ(s.get("/health").status, 200);
    EXPECT_EQ(s.get("/ready").status, 200) << "a second probe commits again";
    EXPECT_EQ(s.get("/v1/maps").body.at("total"), 0) << "the probe is no map";
}

// The disk fills up (RLIMIT_FSIZE: no file of the server may grow past 1 MiB, so SQLite's
// writes to the WAL fail with EFBIG). Writes answer 503 storage_unavailable and leave nothing
// behind, /ready turns 503 naming the file, /health stays 200, reads keep working, and a
// restart with room again is ready with every committed row.
TEST(ServerStorage, AFullDiskIs503StorageUnavailableAndNotReady) {
    if (locus::testing::on_postgres()) GTEST_SKIP() << "fills the SQLite file (PostgreSQL's faults: server_postgres_test)";
    ServerProcess s{{"--quiet"}, FileSizeLimit{1 << 20}};
    ASSERT_EQ(s.get("/ready").status, 200) << s.log();
    const auto h = locus::testing::make_hierarchy(s);
    const std::string imports = "/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import";
    int stored = 1;  // make_hierarchy's radio map
    Response refused;
    for (int i = 0; i < 40; ++i) {
        refused = s.post(imports, radiomap_doc("fill-" + std::to_string(i), 60, 30));
        if (refused.status != 201) break;
        ++stored;
    }
    expect_unavailable(refused, "the import that no longer fits");
    EXPECT_EQ(s.get("/health").status, 200);
    // A small commit may still fit where the import did not; /ready commits until none does.
    Response ready;
    for (int i = 0; i < 400; ++i) {
        ready = s.get("/ready");
        if (ready.status != 200) break;
    }
    expect_unavailable(ready, "/ready on a full disk");
    EXPECT_NE(ready.body["error"]["message"].get<std::string>().find(s.db_path()), std::string::npos)
        << "the message names the database file: " << ready.raw;
    expect_unavailable(s.post("/v1/maps", {{"name", "one more"}}), "a small write on a full disk");
    expect_unavailable(s.post("/v1/radiomaps/" + std::to_string(h.radiomap) + "/rps", {{"name", "p"}, {"x", 1}, {"y", 1}}),
                       "an RP on a full disk");
    EXPECT_EQ(s.get("/health").status, 200) << "liveness does not depend on the disk";
    // Nothing partial: exactly the committed radio maps, each whole.
    const auto list = s.get("/v1/floors/" + std::to_string(h.floor) + "/radiomaps?limit=100");
    ASSERT_EQ(list.status, 200) << list.raw;
    EXPECT_EQ(list.body.at("total"), stored);
    EXPECT_EQ(s.get("/v1/maps").body.at("total"), 1);
    for (const auto& rm : list.body.at("items")) {
        if (rm.at("name") == "survey") continue;
        const auto rps = s.get("/v1/radiomaps/" + std::to_string(rm.at("id").get<long long>()) + "/rps?limit=1");
        ASSERT_EQ(rps.status, 200) << rps.raw;
        EXPECT_EQ(rps.body.at("total"), 60) << rm.dump();
    }
    EXPECT_NE(s.log().find("storage"), std::string::npos) << "the fault is logged:\n" << s.log();

    // Room again: the same database is ready and holds exactly what was committed.
    EXPECT_EQ(s.stop(), 0);
    s.set_file_size_limit(0);
    s.start();
    EXPECT_EQ(s.get("/ready").status, 200);
    EXPECT_EQ(s.get("/v1/floors/" + std::to_string(h.floor) + "/radiomaps").body.at("total"), stored);
    EXPECT_EQ(s.post("/v1/maps", {{"name", "one more"}}).status, 201);
}

// Another process holds the write lock (BEGIN EXCLUSIVE) past the server's busy timeout.
TEST(ServerStorage, ALockedDatabaseIs503UntilTheLockGoes) {
    if (locus::testing::on_postgres()) GTEST_SKIP() << "locks the SQLite file (PostgreSQL's faults: server_postgres_test)";
    ServerProcess s{{"--quiet"}};
    ASSERT_EQ(s.get("/ready").status, 200);
    sqlite3* other = nullptr;
    ASSERT_EQ(sqlite3_open(s.db_path().c_str(), &other), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(other, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(other);
    EXPECT_EQ(s.get("/health").status, 200);
    expect_unavailable(s.post("/v1/maps", {{"name", "blocked"}}), "a write while another process holds the lock");
    const auto ready = s.get("/ready");
    expect_unavailable(ready, "/ready while another process holds the lock");
    EXPECT_NE(ready.raw.find(s.db_path()), std::string::npos) << ready.raw;
    EXPECT_EQ(sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(other);
    EXPECT_EQ(s.get("/ready").status, 200);
    EXPECT_EQ(s.post("/v1/maps", {{"name", "after"}}).status, 201);
    EXPECT_EQ(s.get("/v1/maps").body.at("total"), 1) << "the refused write left nothing";
}

TEST(ServerStorage, ADatabaseThatCannotBeOpenedStopsTheServerNamingIt) {
    const std::string dir = locus::testing::make_temp_dir();
    {
        const std::string garbage = dir + "/garbage.db";
        std::ofstream out(garbage, std::ios::binary);
        for (int i = 0; i < 4096; ++i) out << "not a database " << i << '\n';
        out.close();
        expect_refused_at_start(garbage, "a file of garbage bytes");
    }
    std::filesystem::create_directory(dir + "/a-directory.db");
    expect_refused_at_start(dir + "/a-directory.db", "a directory");
    expect_refused_at_start(dir + "/missing/locus.db", "a path in a missing directory");
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace server_storage_test
