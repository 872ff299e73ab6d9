// PostgreSQL's faults (docs/deploy.md, "Failure behaviour"): unreachable at start (a clear message
// naming the URL without its password, exit non-zero), a schema newer than the binary (refused),
// lost mid-run (writes answer 503 storage_unavailable, localize keeps serving from memory, writes
// work again once it is back). Runs only under scripts/with_postgres.sh.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_postgres_test {
namespace {

using locus::testing::ServerProcess;
using nlohmann::json;

#define REQUIRE_POSTGRES()                                                                                   \
    if (!locus::testing::on_postgres())                                                                      \
    GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh (LOCUS_TEST_DB_URL)"

json m(const std::string& bssid, double rss) { return {{"type", "wifi"}, {"bssid", bssid}, {"mean", rss}, {"variance", 1.0}, {"count", 10}}; }

std::string database_of(const std::string& url) { return url.substr(url.rfind('/') + 1); }

TEST(Postgres, AnUnreachableServerStopsTheStartNamingTheUrlWithoutItsPassword) {
    REQUIRE_POSTGRES();
    const std::string url = "postgresql://locus:hunter2@127.0.0.1:1/nowhere";
    const auto r = locus::testing::run_command({LOCUS_SERVER_BIN, "--db", url, "--port", "0"});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("cannot connect to PostgreSQL at 'postgresql://locus@127.0.0.1:1/nowhere'"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("hunter2"), std::string::npos) << r.err;
}

TEST(Postgres, ASchemaNewerThanTheServerIsRefused) {
    REQUIRE_POSTGRES();
    ServerProcess s({"--quiet"});
    s.stop();
    locus::testing::database_exec(s.db(), "UPDATE locus_schema SET version = version + 1");
    try {
        s.start();
        ADD_FAILURE() << "the server started on a newer schema";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("is newer than this server understands"), std::string::npos) << e.what();
    }
}

TEST(Postgres, LostMidRunWritesAre503LocalizeServesAndWritesComeBack) {
    REQUIRE_POSTGRES();
    ServerProcess s({"--quiet"});
    const auto h = locus::testing::make_hierarchy(s);
    const json doc = {{"name", "rm"},
                      {"rps", {{{"name", "a"}, {"x", 1.0}, {"y", 1.0}, {"scans", 5}, {"measurements", {m("aa:00:00:00:00:01", -40)}}},
                               {{"name", "b"}, {"x", 9.0}, {"y", 1.0}, {"scans", 5}, {"measurements", {m("aa:00:00:00:00:01", -80)}}}}}};
    const auto imported = s.post("/v1/floors/" + std::to_string(h.floor) + "/radiomaps/import", doc);
    ASSERT_EQ(imported.status, 201) << imported.raw;
    const std::string localize = "/v1/radiomaps/" + std::to_string(imported.body.at("id").get<long long>()) + "/localize";
    const json scan = {{"algorithm", "nn"}, {"scans", json::array({json::array({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -41}}})})}};
    ASSERT_EQ(s.post(localize, scan).status, 200);

    const std::string name = database_of(s.db());
    locus::testing::cluster_exec("ALTER DATABASE " + name + " ALLOW_CONNECTIONS false");
    locus::testing::cluster_exec("SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE datname = '" + name + "'");
    for (int i = 0; i < 2; ++i) {
        const auto w = s.post("/v1/maps", {{"name", "while away " + std::to_string(i)}});
        EXPECT_EQ(w.status, 503) << w.raw;
        EXPECT_EQ(w.body.at("error").at("code"), "storage_unavailable") << w.raw;
    }
    EXPECT_EQ(s.get("/ready").status, 503);
    const auto r = s.post(localize, scan);
    EXPECT_EQ(r.status, 200) << r.raw;
    EXPECT_EQ(r.body.at("x"), 1.0);

    locus::testing::cluster_exec("ALTER DATABASE " + name + " ALLOW_CONNECTIONS true");
    // After a failed reconnect the server tries again once a second (requests meanwhile fail
    // at once rather than each waiting out the connect timeout): back within a few seconds.
    int status = 0;
    for (int i = 0; i < 40 && status != 201; ++i) {
        if (i > 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        status = s.post("/v1/maps", {{"name", "back"}}).status;
        if (status != 201) {
            EXPECT_EQ(status, 503);
        }
    }
    EXPECT_EQ(status, 201);
    EXPECT_EQ(s.get("/ready").status, 200);
    EXPECT_EQ(s.get("/v1/maps").body.at("total"), 2) << "only the map before and the one after";
}

}  // namespace
}  // namespace server_postgres_test
