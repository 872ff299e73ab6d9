// `locus import uji|find3|anyplace` on the real samples in LOCUS_DATA_DIR (skipped when the
// folder is absent): what lands in the server, and that a re-run changes no count.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace import_sources_test {
namespace {

using locus::testing::run_command;
using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

const std::string kData = LOCUS_DATA_DIR;

#define REQUIRE_DATA(rel)                                                                              \
    if (!std::filesystem::exists(kData + "/" + rel))                                                   \
    GTEST_SKIP() << kData << "/" << rel << " not found: the shared data folder is absent"

struct Totals {
    std::int64_t rps = 0, scans = 0, measurements = 0, samples = 0;
    bool operator==(const Totals&) const = default;
};

// Sums over every radio map of every floor of every building of the map.
Totals totals(const ServerProcess& s, std::int64_t map) {
    Totals t;
    const auto list = [&](const std::string& path) { return body_of(s.get(path + "?limit=1000"))["items"]; };
    for (const auto& b : list("/v1/maps/" + std::to_string(map) + "/buildings"))
        for (const auto& f : list("/v1/buildings/" + std::to_string(b["id"].get<int>()) + "/floors"))
            for (const auto& rm : list("/v1/floors/" + std::to_string(f["id"].get<int>()) + "/radiomaps")) {
                const json doc = body_of(s.get("/v1/radiomaps/" + std::to_string(rm["id"].get<int>()) + "/export"));
                for (const auto& rp : doc["rps"]) {
                    ++t.rps;
                    t.scans += rp["scans"].get<std::int64_t>();
                    for (const auto& m : rp["measurements"]) {
                        ++t.measurements;
                        t.samples += m["count"].get<std::int64_t>();
                    }
                }
            }
    return t;
}

// The summary of a run that must succeed; a failed run stops the test here, with its stderr,
// instead of later on a field of no summary.
json run_ok(const std::vector<std::string>& argv) {
    const auto r = run_command(argv);
    if (r.status != 0) throw std::runtime_error("exit status " + std::to_string(r.status) + ":\n" + r.err);
    return json::parse(r.out);
}

TEST(ImportFind3, OneRoomAndOneRpPerLabel) {
    REQUIRE_DATA("find3/testdb.learn.1439597065993.jsons");
    ServerProcess server{{"--quiet"}};
    const std::string file = kData + "/find3/testdb.learn.1439597065993.jsons";
    const json first = run_ok({LOCUS_CLI_BIN, "import", "find3", "--server", server.url(), "--map", "Home", "--no-progress", file});
    EXPECT_EQ(first["rps"], 3);  // three labels in the sample
    EXPECT_EQ(first["scans"], 343);
    EXPECT_EQ(first["malformed_lines"], 0);
    const auto rooms = body_of(server.get("/v1/floors/" + std::to_string(first["floor_id"].get<int>()) + "/rooms"));
    EXPECT_EQ(rooms["total"], 3);
    // Each RP sits at its room's centre, so localizing its own scan names the room.
    const auto rps = body_of(server.get("/v1/radiomaps/" + std::to_string(first["radiomap_id"].get<int>()) + "/rps"))["items"];
    ASSERT_EQ(rps.size(), 3u);
    const Totals before = totals(server, first["map_id"].get<int>());
    EXPECT_EQ(before.scans, 343);
    const json again = run_ok({LOCUS_CLI_BIN, "import", "find3", "--server", server.url(), "--map", "Home", "--no-progress", file});
    EXPECT_EQ(again["already_uploaded"], 3);
    EXPECT_EQ(again["rooms_created"], 0);
    EXPECT_TRUE(totals(server, first["map_id"].get<int>()) == before);
}

TEST(ImportAnyplace, TwoFloorsInLocalMetres) {
    REQUIRE_DATA("anyplace/hotelpitt");
    ServerProcess server{{"--quiet"}};
    const std::string dir = kData + "/anyplace/hotelpitt";
    // Expected figures straight from the files: distinct (floor, lat, lon) and lines.
    std::set<std::string> points;
    std::size_t lines = 0;
    for (const char* floor : {"0", "1"}) {
        std::ifstream in(dir + "/" + floor + "/rss-log");
        for (std::string l; std::getline(in, l);) {
            if (l.empty() || l[0] == '#') continue;
            std::istringstream ss(l);
            std::string t, lat, lon, heading, bssid, rss, fl;
            ss >> t >> lat >> lon >> heading >> bssid >> rss >> fl;
            points.insert(fl + " " + lat + " " + lon);
            ++lines;
        }
    }
    const json first = run_ok({LOCUS_CLI_BIN, "import", "anyplace", "--server", server.url(), "--map", "Hotels", "--no-progress", dir});
    EXPECT_EQ(first["floors"], 2);
    EXPECT_EQ(first["rps"].get<std::size_t>(), points.size());
    EXPECT_LE(first["readings"].get<std::size_t>(), lines);  // an AP repeated within one scan is kept once
    EXPECT_GT(first["readings"].get<std::size_t>(), lines * 9 / 10);
    const Totals before = totals(server, first["map_id"].get<int>());
    EXPECT_EQ(static_cast<std::size_t>(before.rps), points.size());
    EXPECT_EQ(static_cast<std::size_t>(before.samples), first["readings"].get<std::size_t>());
    // Floors are a hotel's size in metres, not degrees.
    const auto floors = body_of(server.get("/v1/buildings/" + std::to_string(first["building_id"].get<int>()) + "/floors"))["items"];
    ASSERT_EQ(floors.size(), 2u);
    for (const auto& f : floors) {
        EXPECT_GT(f["width"].get<double>(), 5.0);
        EXPECT_LT(f["width"].get<double>(), 500.0);
        EXPECT_LT(f["height"].get<double>(), 500.0);
    }
    const json again = run_ok({LOCUS_CLI_BIN, "import", "anyplace", "--server", server.url(), "--map", "Hotels", "--no-progress", dir});
    EXPECT_EQ(again["applied"], 0);
    EXPECT_TRUE(totals(server, first["map_id"].get<int>()) == before);
}

TEST(ImportUji, FullTrainingFileInterruptedThenResumed) {
    REQUIRE_DATA("ujiindoorloc/trainingData.csv");
    ServerProcess server{{"--quiet"}};
    const std::string file = kData + "/ujiindoorloc/trainingData.csv";
    const std::vector<std::string> base{LOCUS_CLI_BIN, "import", "uji", "--server", server.url(), "--map", "UJI", "--no-progress"};
    auto with = [&](std::vector<std::string> extra) {
        auto argv = base;
        argv.insert(argv.end(), extra.begin(), extra.end());
        argv.push_back(file);
        return argv;
    };
    const auto cut = run_command(with({"--stop-after", "100"}));
    EXPECT_EQ(cut.status, 3) << cut.err;
    const json rest = run_ok(with({}));
    EXPECT_EQ(rest["rps"], 933);  // distinct (building, floor, longitude, latitude)
    EXPECT_EQ(rest["already_uploaded"], 100);
    EXPECT_EQ(rest["applied"], 833);
    EXPECT_EQ(rest["radiomaps"], 13);  // 4 + 4 + 5 floors
    const Totals t = totals(server, rest["map_id"].get<int>());
    EXPECT_EQ(t.rps, 933);
    EXPECT_EQ(t.scans, 19937);
    const json again = run_ok(with({}));
    EXPECT_EQ(again["applied"], 0);
    EXPECT_TRUE(totals(server, rest["map_id"].get<int>()) == t);
    EXPECT_EQ(t.samples, again["readings"].get<std::int64_t>());  // every valid reading merged exactly once
}

TEST(ImportUji, LocalizeAnswersComeBackInCsvCoordinates) {
    REQUIRE_DATA("ujiindoorloc/trainingData.csv");
    ServerProcess server{{"--quiet"}};
    const std::string file = kData + "/ujiindoorloc/trainingData.csv";
    const json out = run_ok({LOCUS_CLI_BIN, "import", "uji", "--server", server.url(), "--no-progress", file});
    const int map = out["map_id"].get<int>();
    // The first data row of the CSV: building 1, floor 2 at (-7541.2643, 4864920.7782).
    const std::string rp_name = "b1f2_-7541.2643_4864920.7782";
    const auto list = [&](const std::string& path) { return body_of(server.get(path + "?limit=1000"))["items"]; };
    json rp;
    for (const auto& b : list("/v1/maps/" + std::to_string(map) + "/buildings"))
        if (b["name"] == "Building 1")
            for (const auto& f : list("/v1/buildings/" + std::to_string(b["id"].get<int>()) + "/floors"))
                if (f["name"] == "Floor 2")
                    for (const auto& rm : list("/v1/floors/" + std::to_string(f["id"].get<int>()) + "/radiomaps")) {
                        const json doc = body_of(server.get("/v1/radiomaps/" + std::to_string(rm["id"].get<int>()) + "/export"));
                        for (const auto& r : doc["rps"])
                            if (r["name"] == rp_name) rp = r;
                    }
    ASSERT_TRUE(rp.is_object()) << "no RP " << rp_name;
    // Querying with the RP's own means: its kNN distance (missing APs at the floor value) is 0, so the
    // map-wide answer is that RP, and adding the building origin gives the CSV's position.
    json means = json::array();
    for (const auto& m : rp["measurements"]) means.push_back({{"bssid", m["bssid"]}, {"mean", m["mean"]}});
    const auto r = server.post("/v1/maps/" + std::to_string(map) + "/localize", {{"algorithm", "knn"}, {"measurements", means}, {"options", {{"k", 1}}}});
    ASSERT_EQ(r.status, 200) << r.raw;
    const json origin = out["origins"]["1"];
    EXPECT_EQ(r.body["building_id"], origin["building_id"]);
    EXPECT_NEAR(r.body["x"].get<double>() + origin["x0"].get<double>(), -7541.2643, 1e-3);
    EXPECT_NEAR(r.body["y"].get<double>() + origin["y0"].get<double>(), 4864920.7782, 1e-3);
}

}  // namespace
}  // namespace import_sources_test
