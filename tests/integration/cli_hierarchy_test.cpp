// `locus map create`, `locus building create`, `locus floor create` against the real server:
// each prints what it made; what is missing is said all at once and nothing is sent.
#include <gtest/gtest.h>

#include <filesystem>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace cli_hierarchy_test {
namespace {

using locus::testing::run_command;
using locus::testing::ServerProcess;
using nlohmann::json;

TEST(CliHierarchy, AMapABuildingAndAFloorFromScratch) {
    ServerProcess s;
    const auto map = run_command({LOCUS_CLI_BIN, "map", "create", "--server", s.url(), "--name", "Campus", "--description", "ours"});
    ASSERT_EQ(map.status, 0) << map.err;
    const json m = json::parse(map.out);
    EXPECT_EQ(m.at("name"), "Campus");
    EXPECT_EQ(m.at("description"), "ours");
    const std::string map_id = std::to_string(m.at("id").get<long long>());

    const auto building = run_command({LOCUS_CLI_BIN, "building", "create", "--server", s.url(), "--map", map_id, "--name", "Main"});
    ASSERT_EQ(building.status, 0) << building.err;
    const std::string building_id = std::to_string(json::parse(building.out).at("id").get<long long>());

    const auto floor = run_command({LOCUS_CLI_BIN, "floor", "create", "--server", s.url(), "--building", building_id, "--name", "Ground",
                                    "--width", "40", "--height", "25.5", "--north-offset", "12"});
    ASSERT_EQ(floor.status, 0) << floor.err;
    const json f = json::parse(floor.out);
    EXPECT_EQ(f.at("level"), 0);  // the default: the ground floor
    EXPECT_EQ(f.at("width"), 40.0);
    EXPECT_EQ(f.at("height"), 25.5);
    EXPECT_EQ(f.at("north_offset_deg"), 12.0);
    const auto listed = s.get("/v1/buildings/" + building_id + "/floors");
    EXPECT_EQ(listed.body.at("total"), 1);
}

TEST(CliHierarchy, WhatIsMissingIsSaidAtOnceAndNothingIsSent) {
    ServerProcess s;
    const auto r = run_command({LOCUS_CLI_BIN, "floor", "create", "--server", s.url(), "--name", "F"});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--building, --width and --height are required"), std::string::npos) << r.err;
    const auto m = run_command({LOCUS_CLI_BIN, "map", "create", "--server", s.url()});
    EXPECT_EQ(m.status, 2);
    EXPECT_NE(m.err.find("--name is required"), std::string::npos) << m.err;
    EXPECT_EQ(s.get("/v1/maps").body.at("total"), 0);
}

TEST(CliHierarchy, TheServersRefusalIsShown) {
    ServerProcess s;
    ASSERT_EQ(run_command({LOCUS_CLI_BIN, "map", "create", "--server", s.url(), "--name", "Twice"}).status, 0);
    const auto again = run_command({LOCUS_CLI_BIN, "map", "create", "--server", s.url(), "--name", "Twice"});
    EXPECT_NE(again.status, 0);
    EXPECT_NE(again.err.find("a map with that name already exists"), std::string::npos) << again.err;
    const auto bad = run_command({LOCUS_CLI_BIN, "floor", "create", "--server", s.url(), "--building", "999", "--name", "F", "--width", "1",
                                  "--height", "1"});
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.err.find("999"), std::string::npos) << bad.err;
    EXPECT_EQ(s.get("/v1/maps").body.at("total"), 1);
}

TEST(CliHierarchy, APlanExportedFromOneFloorImportsOnAnother) {
    ServerProcess s({"--demo"});
    const std::string dir = locus::testing::make_temp_dir();
    const auto exported = run_command({LOCUS_CLI_BIN, "plan", "export", "--server", s.url(), "--floor", "1", "-o", dir + "/plan.geojson"});
    ASSERT_EQ(exported.status, 0) << exported.err;
    const auto floor = run_command({LOCUS_CLI_BIN, "floor", "create", "--server", s.url(), "--building", "1", "--name", "Annex",
                                    "--level", "2", "--width", "30", "--height", "15"});
    ASSERT_EQ(floor.status, 0) << floor.err;
    const std::string id = std::to_string(json::parse(floor.out).at("id").get<long long>());
    const auto imported = run_command({LOCUS_CLI_BIN, "plan", "import", "--server", s.url(), "--floor", id, dir + "/plan.geojson"});
    ASSERT_EQ(imported.status, 0) << imported.err;
    EXPECT_NE(imported.err.find("made for another floor"), std::string::npos) << imported.err;
    // The rooms were made on the new floor from the spaces' names.
    const auto rooms = s.get("/v1/floors/" + id + "/rooms");
    EXPECT_GT(rooms.body.at("total").get<int>(), 0) << rooms.raw;
    const auto source_rooms = s.get("/v1/floors/1/rooms");
    EXPECT_EQ(rooms.body.at("total"), source_rooms.body.at("total"));
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cli_hierarchy_test
