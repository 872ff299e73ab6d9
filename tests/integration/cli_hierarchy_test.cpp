// `locus map create`, `locus building create`, `locus floor create` against the real server:
// each prints what it made; what is missing is said all at once and nothing is sent. `list`
// shows what there is, as a table or JSON; `--version` says which Locus it is.
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

// Every map, 120 (more than a page of the server's default size), listed as JSON; then a
// building's floors as a table whose header names the columns and whose rows line up.
TEST(CliHierarchy, ListShowsWhatThereIsAsATableOrJson) {
    ServerProcess s;
    for (int i = 0; i < 120; ++i) ASSERT_EQ(s.post("/v1/maps", {{"name", "Site " + std::to_string(i)}}).status, 201) << i;
    const auto maps = run_command({LOCUS_CLI_BIN, "map", "list", "--server", s.url(), "--json"});
    ASSERT_EQ(maps.status, 0) << maps.err;
    const json all = json::parse(maps.out);
    ASSERT_EQ(all.size(), 120u);
    EXPECT_EQ(all.back().at("name"), "Site 119");
    const std::string map_id = std::to_string(all.front().at("id").get<long long>());
    const auto building = s.post("/v1/maps/" + map_id + "/buildings", {{"name", "Main"}});
    const std::string building_id = std::to_string(building.body.at("id").get<long long>());
    for (const auto& [name, level] : {std::pair{"Ground", 0}, std::pair{"Basement level", -1}})
        ASSERT_EQ(s.post("/v1/buildings/" + building_id + "/floors", {{"name", name}, {"level", level}, {"width", 40.0}, {"height", 25.5}}).status, 201);
    const auto floors = run_command({LOCUS_CLI_BIN, "floor", "list", "--server", s.url(), "--building", building_id});
    ASSERT_EQ(floors.status, 0) << floors.err;
    std::vector<std::string> lines;
    for (std::size_t at = 0, end; (end = floors.out.find('\n', at)) != std::string::npos; at = end + 1) lines.push_back(floors.out.substr(at, end - at));
    ASSERT_EQ(lines.size(), 3u) << floors.out;
    EXPECT_TRUE(lines[0].starts_with("id")) << lines[0];
    // Each column starts where its header does.
    const std::size_t name_at = lines[0].find("name"), width_at = lines[0].find("width");
    ASSERT_NE(name_at, std::string::npos);
    for (const std::string& row : {lines[1], lines[2]}) {
        EXPECT_EQ(row.find_first_not_of(' ', name_at), name_at) << row;
        EXPECT_EQ(row.substr(width_at, 4), "40.0") << row;
    }
    EXPECT_NE(floors.out.find("Ground"), std::string::npos);
    EXPECT_NE(floors.out.find("Basement level"), std::string::npos);
    EXPECT_NE(floors.out.find("-1"), std::string::npos);
    const auto none = run_command({LOCUS_CLI_BIN, "building", "list", "--server", s.url()});
    EXPECT_EQ(none.status, 2);
    EXPECT_NE(none.err.find("--map is required"), std::string::npos) << none.err;
    const auto unknown = run_command({LOCUS_CLI_BIN, "floor", "list", "--server", s.url(), "--building", "999"});
    EXPECT_NE(unknown.status, 0);
    EXPECT_NE(unknown.err.find("999"), std::string::npos) << unknown.err;
}

// Every command finds the server alike: --server, else $LOCUS_SERVER (else 127.0.0.1:8080).
TEST(CliHierarchy, LocusServerNamesTheServerWhenServerIsNotGiven) {
    ServerProcess s;
    const auto made = run_command({LOCUS_CLI_BIN, "map", "create", "--name", "From the environment"}, {"LOCUS_SERVER=" + s.url()});
    ASSERT_EQ(made.status, 0) << made.err;
    const auto listed = run_command({LOCUS_CLI_BIN, "map", "list", "--json"}, {"LOCUS_SERVER=" + s.url()});
    ASSERT_EQ(listed.status, 0) << listed.err;
    EXPECT_EQ(json::parse(listed.out).at(0).at("name"), "From the environment");
    // --server wins over the environment.
    const auto given = run_command({LOCUS_CLI_BIN, "map", "list", "--json", "--server", s.url()}, {"LOCUS_SERVER=http://127.0.0.1:1"});
    EXPECT_EQ(given.status, 0) << given.err;
}

TEST(CliHierarchy, BothProgramsSayTheirVersion) {
    for (const auto& [bin, name] : {std::pair{LOCUS_CLI_BIN, "locus "}, std::pair{LOCUS_SERVER_BIN, "locus-server "}}) {
        const auto r = run_command({bin, "--version"});
        EXPECT_EQ(r.status, 0) << bin << ": " << r.err;
        EXPECT_TRUE(r.out.starts_with(name)) << r.out;
        // A version is numbers and dots (CMakeLists.txt's project()).
        const std::string v = r.out.substr(std::string(name).size());
        EXPECT_FALSE(v.empty());
        EXPECT_EQ(v.find_first_not_of("0123456789.\n"), std::string::npos) << r.out;
    }
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
