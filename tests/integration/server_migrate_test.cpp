// `locus migrate --from sqlite:PATH --to postgresql://…` (docs/deploy.md, "Moving an SQLite
// database into PostgreSQL"): a server on the copy answers what the SQLite server answered, ids
// included and never reused; a non-empty target is refused. Runs only under
// scripts/with_postgres.sh.
#include <gtest/gtest.h>

#include <string>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "build_paths.hpp"

namespace server_migrate_test {
namespace {

using locus::testing::body_of;
using locus::testing::SameDatabase;
using locus::testing::ServerProcess;
using nlohmann::json;

TEST(Migrate, ASqliteDatabaseMovesToPostgresWithItsIdsAndIsVerified) {
    if (!locus::testing::on_postgres()) GTEST_SKIP() << "needs PostgreSQL: run under scripts/with_postgres.sh";
    const std::string dir = locus::testing::make_temp_dir();
    const std::string file = dir + "/source.db";
    json exported, floors;
    std::int64_t radiomap = 0;
    {
        ServerProcess sqlite({"--quiet", "--demo"}, SameDatabase{file});  // a path: SQLite
        ASSERT_EQ(sqlite.post("/v1/maps", {{"name", "deleted"}}).status, 201);
        ASSERT_EQ(sqlite.del("/v1/maps/2").status, 204);
        const auto h = locus::testing::make_hierarchy(sqlite, "second");
        radiomap = h.radiomap;
        const auto rp = locus::testing::make_rp(sqlite, h.radiomap, "rp", 1.5, 2.25);
        ASSERT_EQ(sqlite.post("/v1/rps/" + std::to_string(rp) + "/scans",
                              {{"upload_id", "u1"}, {"scans", json::array({json::array({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -61.5}}})})}})
                      .status,
                  200);
        exported = body_of(sqlite.get("/v1/radiomaps/" + std::to_string(radiomap) + "/export"));
        floors = body_of(sqlite.get("/v1/buildings/1/floors"));
    }
    locus::testing::TestDatabase target;
    const auto moved = locus::testing::run_command({LOCUS_CLI_BIN, "migrate", "--from", "sqlite:" + file, "--to", target.url()});
    ASSERT_EQ(moved.status, 0) << moved.err;
    EXPECT_NE(moved.out.find("every table compares equal"), std::string::npos) << moved.out;

    {
        ServerProcess pg({"--quiet"}, SameDatabase{target.url()});
        EXPECT_EQ(body_of(pg.get("/v1/radiomaps/" + std::to_string(radiomap) + "/export")), exported);
        EXPECT_EQ(body_of(pg.get("/v1/buildings/1/floors")), floors);
        const auto created = body_of(pg.post("/v1/maps", {{"name", "after"}}), 201);
        EXPECT_GT(created.at("id").get<std::int64_t>(), 3) << "an id the SQLite database handed out is handed out again";
        // The upload id came along: the same upload again is a repeat.
        const auto rps = body_of(pg.get("/v1/radiomaps/" + std::to_string(radiomap) + "/rps"));
        const auto again = pg.post("/v1/rps/" + std::to_string(rps.at("items")[0].at("id").get<std::int64_t>()) + "/scans",
                                   {{"upload_id", "u1"}, {"scans", json::array({json::array({{{"bssid", "aa:00:00:00:00:01"}, {"rss", -61.5}}})})}});
        ASSERT_EQ(again.status, 200) << again.raw;
        EXPECT_FALSE(again.body.at("applied").get<bool>());
    }
    const auto refused = locus::testing::run_command({LOCUS_CLI_BIN, "migrate", "--from", "sqlite:" + file, "--to", target.url()});
    EXPECT_NE(refused.status, 0);
    EXPECT_NE(refused.err.find("needs an empty database"), std::string::npos) << refused.err;
    const auto missing = locus::testing::run_command({LOCUS_CLI_BIN, "migrate", "--from", "sqlite:" + file, "--to", "postgresql://locus@127.0.0.1:1/none"});
    EXPECT_NE(missing.status, 0);
    EXPECT_NE(missing.err.find("cannot connect to PostgreSQL"), std::string::npos) << missing.err;
    [[maybe_unused]] int rc = std::system(("rm -rf '" + dir + "'").c_str());
}

}  // namespace
}  // namespace server_migrate_test
