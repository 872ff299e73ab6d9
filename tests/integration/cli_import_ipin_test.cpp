// `locus import ipin`, `locus survey walk` and `locus eval ipin` against a real server, on the
// tiny IPIN-like folder tests/fixtures/ipin_import (two short walks written by hand: T01 on
// floor 0 along (70,40) → (80,40) → (80,50) at 1 m/s, scans every 2 s; T52 from floor 0 down
// the stairs to floor -2; two beacons). Expected positions are worked out by hand from those
// landmarks; the fixture's lat/lon were made with the data set's equirectangular frame,
// which agrees with the tangent plane to about a centimetre.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "server_process.hpp"
#include "text_file.hpp"
#include "build_paths.hpp"

namespace cli_import_ipin_test {
namespace {

using locus::testing::body_of;
using locus::testing::make_temp_dir;
using locus::testing::run_command;
using locus::testing::ServerProcess;
using nlohmann::json;
namespace fs = std::filesystem;

const std::string kFixture = std::string(LOCUS_TEST_FIXTURES) + "/ipin_import";
const std::string kT01 = kFixture + "/trials/IPIN2023_T3_TrainingTrial01_repetition01.txt";

std::vector<json> items(const ServerProcess& s, const std::string& path) {
    return body_of(s.get(path + (path.find('?') == std::string::npos ? "?limit=1000" : "&limit=1000")))["items"].get<std::vector<json>>();
}

// RP names end in the walk file's content hash: "<stem> <cell>m #<k> <8 hex digits>".
json by_name(const std::vector<json>& rows, const std::string& name) {
    for (const auto& r : rows) {
        const std::string n = r["name"].get<std::string>();
        if (n == name || (n.size() == name.size() + 9 && n.compare(0, name.size() + 1, name + " ") == 0)) return r;
    }
    ADD_FAILURE() << "no row named '" << name << "'";
    return json::object();
}

// Everything the import writes, as the server answers it, for comparing two runs.
json state(const ServerProcess& s, std::int64_t map_id) {
    json out = json::object();
    for (const auto& b : items(s, "/v1/maps/" + std::to_string(map_id) + "/buildings")) {
        out["buildings"].push_back(b);
        for (const auto& f : items(s, "/v1/buildings/" + std::to_string(b["id"].get<std::int64_t>()) + "/floors")) {
            const std::string fid = std::to_string(f["id"].get<std::int64_t>());
            out["floors"].push_back(f);
            for (const auto& t : items(s, "/v1/floors/" + fid + "/transmitters")) out["transmitters"].push_back(t);
            for (const auto& rm : items(s, "/v1/floors/" + fid + "/radiomaps")) {
                out["radiomaps"].push_back(rm);
                for (const auto& rp : items(s, "/v1/radiomaps/" + std::to_string(rm["id"].get<std::int64_t>()) + "/rps"))
                    out["rps"].push_back(body_of(s.get("/v1/rps/" + std::to_string(rp["id"].get<std::int64_t>()))));
            }
        }
    }
    return out;
}

std::string copy_fixture() {
    const std::string dir = make_temp_dir() + "/ipin";
    fs::copy(kFixture, dir, fs::copy_options::recursive);
    return dir;
}

void replace_line(const std::string& path, int line_no, const std::string& text) {
    std::ifstream in(path);
    std::string all, line;
    for (int n = 1; std::getline(in, line); ++n) all += (n == line_no ? text : line) + "\n";
    std::ofstream(path) << all;
}

std::size_t map_count(const ServerProcess& s) { return body_of(s.get("/v1/maps"))["total"].get<std::size_t>(); }

TEST(ImportIpin, CreatesTheVenueAndASecondRunChangesNothing) {
    ServerProcess server{{"--quiet"}};
    const auto r = run_command({LOCUS_CLI_BIN, "import", "ipin", kFixture, "--server", server.url(), "--cell", "5", "--no-progress"});
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    const auto map_id = out["map_id"].get<std::int64_t>();
    EXPECT_EQ(body_of(server.get("/v1/maps/" + std::to_string(map_id)))["name"], "IPIN 2023 Nuremberg");
    EXPECT_EQ(out["walk"]["skipped_before_first"], 5);   // T01: 2, 4, 6, 8 s; T52: 4 s
    EXPECT_EQ(out["walk"]["skipped_after_last"], 3);     // T01: 32, 34 s; T52: 54 s
    EXPECT_EQ(out["walk"]["skipped_floor_change"], 3);   // T52 on the stairs: 24, 30, 36 s
    EXPECT_EQ(out["walk"]["placed"], 15);
    EXPECT_EQ(out["transmitters"]["created"], 2);

    const auto buildings = items(server, "/v1/maps/" + std::to_string(map_id) + "/buildings");
    ASSERT_EQ(buildings.size(), 1u);
    EXPECT_EQ(buildings[0]["name"], "100");
    const auto floors = items(server, "/v1/buildings/" + std::to_string(buildings[0]["id"].get<std::int64_t>()) + "/floors");
    ASSERT_EQ(floors.size(), 3u);
    std::map<int, json> floor_of;
    for (const auto& f : floors) floor_of[f["level"].get<int>()] = f;
    ASSERT_EQ(floor_of.size(), 3u);
    EXPECT_DOUBLE_EQ(floor_of[0]["elevation_m"].get<double>(), 0.0);
    EXPECT_DOUBLE_EQ(floor_of[-1]["elevation_m"].get<double>(), 3.2);
    EXPECT_DOUBLE_EQ(floor_of[-2]["elevation_m"].get<double>(), -5.7);
    for (auto& [level, f] : floor_of) {
        const json& g = f["geo"];
        ASSERT_TRUE(g.is_object()) << level;
        EXPECT_DOUBLE_EQ(g["lat"].get<double>(), 49.46115);
        EXPECT_DOUBLE_EQ(g["lon"].get<double>(), 11.11115);
        EXPECT_DOUBLE_EQ(g["x"].get<double>(), 70.0);
        EXPECT_DOUBLE_EQ(g["y"].get<double>(), 40.0);
        EXPECT_DOUBLE_EQ(g["bearing_deg"].get<double>(), 0.0);
        EXPECT_GE(f["width"].get<double>(), 140.0);
        EXPECT_GE(f["height"].get<double>(), 80.0);
    }
    auto fid = [&](int level) { return std::to_string(floor_of[level]["id"].get<std::int64_t>()); };

    // Beacons: BLE1 at (75, 45) on floor 0, BLE3 at (85, 45) on floor -2; BLE3's place is the
    // logs' beacon 2's (ipin::logged_beacon: the walks put MAC :02 there).
    const auto t0 = items(server, "/v1/floors/" + fid(0) + "/transmitters");
    ASSERT_EQ(t0.size(), 1u);
    EXPECT_EQ(t0[0]["name"], "BLE1");
    EXPECT_EQ(t0[0]["type"], "ble");
    EXPECT_EQ(t0[0]["bssid"], "be:ac:20:23:00:01");
    EXPECT_NEAR(t0[0]["x"].get<double>(), 75.0, 0.02);
    EXPECT_NEAR(t0[0]["y"].get<double>(), 45.0, 0.02);
    const auto t2 = items(server, "/v1/floors/" + fid(-2) + "/transmitters");
    ASSERT_EQ(t2.size(), 1u);
    EXPECT_EQ(t2[0]["bssid"], "be:ac:20:23:00:02");
    EXPECT_NEAR(t2[0]["x"].get<double>(), 85.0, 0.02);
    EXPECT_TRUE(items(server, "/v1/floors/" + fid(-1) + "/transmitters").empty());

    // Radio maps. Floor 0: T01's scans at path 0, 2, ..., 20 m in 5 m bins {0,2,4} {6,8,10}
    // {12,14,16} {18,20}, and T52's two floor-0 scans (72,40), (76,40) in one bin.
    const auto rm0 = items(server, "/v1/floors/" + fid(0) + "/radiomaps");
    ASSERT_EQ(rm0.size(), 1u);
    EXPECT_EQ(rm0[0]["name"], "IPIN 2023 walking survey");
    const auto rps0 = items(server, "/v1/radiomaps/" + std::to_string(rm0[0]["id"].get<std::int64_t>()) + "/rps");
    ASSERT_EQ(rps0.size(), 5u);
    const struct { const char* name; double x, y; int scans; } want0[] = {{"T01_R01 5m #001", 72, 40, 3},
                                                                         {"T01_R01 5m #002", 78, 40, 3},
                                                                         {"T01_R01 5m #003", 80, 44, 3},
                                                                         {"T01_R01 5m #004", 80, 49, 2},
                                                                         {"T52_R01 5m #001", 74, 40, 2}};
    for (const auto& w : want0) {
        const json rp = by_name(rps0, w.name);
        EXPECT_NEAR(rp["x"].get<double>(), w.x, 0.02) << w.name;
        EXPECT_NEAR(rp["y"].get<double>(), w.y, 0.02) << w.name;
        EXPECT_EQ(body_of(server.get("/v1/rps/" + std::to_string(rp["id"].get<std::int64_t>())))["scans"], w.scans) << w.name;
    }
    // Floor -2: T52's scans at (80,46) and (80,50), one bin; the mezzanine gets no radio map.
    const auto rm2 = items(server, "/v1/floors/" + fid(-2) + "/radiomaps");
    ASSERT_EQ(rm2.size(), 1u);
    const auto rps2 = items(server, "/v1/radiomaps/" + std::to_string(rm2[0]["id"].get<std::int64_t>()) + "/rps");
    ASSERT_EQ(rps2.size(), 1u);
    EXPECT_NEAR(rps2[0]["x"].get<double>(), 80.0, 0.02);
    EXPECT_NEAR(rps2[0]["y"].get<double>(), 48.0, 0.02);
    EXPECT_TRUE(items(server, "/v1/floors/" + fid(-1) + "/radiomaps").empty());

    const json before = state(server, map_id);
    const auto again = run_command({LOCUS_CLI_BIN, "import", "ipin", kFixture, "--server", server.url(), "--cell", "5", "--no-progress"});
    ASSERT_EQ(again.status, 0) << again.err;
    const json second = json::parse(again.out);
    EXPECT_EQ(second["map_id"], map_id);
    EXPECT_EQ(second["floors_patched"], 0);
    EXPECT_EQ(second["transmitters"]["unchanged"], 2);
    EXPECT_EQ(second["upload"]["created"], 0);
    EXPECT_EQ(second["upload"]["applied"], 0);
    EXPECT_EQ(second["upload"]["already_uploaded"], 6);
    EXPECT_EQ(state(server, map_id), before);
    EXPECT_EQ(map_count(server), 1u);

    // A map imported before BLE3 had its right MAC (it had :03, its number's): the import moves
    // that row to :02, by its name, and makes no second BLE3.
    const std::string ble3 = "/v1/transmitters/" + std::to_string(t2[0]["id"].get<std::int64_t>());
    ASSERT_EQ(server.patch(ble3, {{"bssid", "be:ac:20:23:00:03"}}).status, 200);
    const auto moved = run_command({LOCUS_CLI_BIN, "import", "ipin", kFixture, "--server", server.url(), "--cell", "5", "--no-progress"});
    ASSERT_EQ(moved.status, 0) << moved.err;
    EXPECT_EQ(json::parse(moved.out)["transmitters"]["updated"], 1);
    const auto t2_after = items(server, "/v1/floors/" + fid(-2) + "/transmitters");
    ASSERT_EQ(t2_after.size(), 1u);
    EXPECT_EQ(t2_after[0]["bssid"], "be:ac:20:23:00:02");
    EXPECT_EQ(t2_after[0]["id"], t2[0]["id"]);
    EXPECT_EQ(state(server, map_id), before);

    // The evaluation scores T52 at its 4 POSI instants against this map.
    const auto ev = run_command({LOCUS_CLI_BIN, "eval", "ipin", kFixture, "--server", server.url(), "--map", std::to_string(map_id),
                                 "--trials", "*Trial52*", "--train", "*Trial01*", "--method", "all", "--json"});
    ASSERT_EQ(ev.status, 0) << ev.err;
    const json e = json::parse(ev.out);
    EXPECT_EQ(e["default"], "walk_pf");  // the default tracker, run last
    EXPECT_EQ(e["pooled"]["wifi"]["n"], 4);
    EXPECT_EQ(e["pooled"]["walk_pf"]["n"], 4);
    EXPECT_EQ(e["pooled"]["pdr"]["n"], 4);
    EXPECT_EQ(e["pooled"]["wifi-baro"]["n"], 4);
    // T52's pressure rises by 0.66 hPa (5.7 m down) between its 24 s and 30 s samples: the two
    // POSI instants after the stairs are on −2 by the barometer, whatever the radio said.
    EXPECT_EQ(e["pooled"]["wifi-baro"]["floor_hit_rate"], 1.0);
    // The trackers take their floor from the same barometer (this file has no ACCE: no step,
    // so they stand on the answers).
    EXPECT_EQ(e["pooled"]["walk_pf"]["floor_hit_rate"], 1.0);
    EXPECT_EQ(e["pooled"]["pdr"]["floor_hit_rate"], 1.0);
    EXPECT_EQ(e["pooled"]["kalman"]["floor_hit_rate"], 1.0);
    EXPECT_EQ(e["pooled"]["yardstick"]["n"], 4);
    ASSERT_EQ(e["trials"].size(), 1u);
    EXPECT_EQ(e["trials"][0]["trial"], "T52_R01");
    EXPECT_EQ(e["trials"][0]["phone"], "SM-G930F");
    // The yardstick maps only floor 0 (T01): the two POSI instants on -2 are 15 m or more off.
    EXPECT_GE(e["trials"][0]["methods"]["yardstick"]["p75_m"].get<double>(), 15.0);
    // walk_pf's live track's own scan fixes are scored at the scans, as the other methods' answers
    // are ("scans"): every scan the map answered has one.
    const json& scan_fixes = e["pooled"]["walk_pf"]["scan_fixes"];
    EXPECT_GT(scan_fixes["n"].get<int>(), 0) << e["pooled"]["walk_pf"].dump();
    EXPECT_EQ(scan_fixes["n"], e["pooled"]["wifi"]["scans"]["n"]) << e["pooled"].dump();
    EXPECT_EQ(e["trials"][0]["methods"]["walk_pf"]["scan_fixes"]["n"], scan_fixes["n"]);
    // --no-subarea opens the live track with its subarea off: the same scans, scored alike.
    const auto off = run_command({LOCUS_CLI_BIN, "eval", "ipin", kFixture, "--server", server.url(), "--map", std::to_string(map_id),
                                  "--trials", "*Trial52*", "--method", "walk_pf", "--no-subarea", "--json"});
    ASSERT_EQ(off.status, 0) << off.err;
    EXPECT_EQ(json::parse(off.out)["pooled"]["walk_pf"]["scan_fixes"]["n"], scan_fixes["n"]);
}

TEST(ImportIpin, BadInputImportsNothing) {
    ServerProcess server{{"--quiet"}};
    const std::string url = server.url();

    const auto missing = run_command({LOCUS_CLI_BIN, "import", "ipin", "/nonexistent/ipin", "--server", url});
    EXPECT_NE(missing.status, 0);
    EXPECT_NE(missing.err.find("'/nonexistent/ipin' is not a folder"), std::string::npos) << missing.err;

    const std::string no_ble = copy_fixture();
    fs::remove(no_ble + "/supplementary/BLE_Locations.csv");
    const auto nb = run_command({LOCUS_CLI_BIN, "import", "ipin", no_ble, "--server", url});
    EXPECT_NE(nb.status, 0);
    EXPECT_NE(nb.err.find("BLE_Locations.csv' is missing"), std::string::npos) << nb.err;

    const std::string bad_csv = copy_fixture();
    replace_line(bad_csv + "/supplementary/BLE_Locations.csv", 3, "\"BLE3\",49.46,eleven,-2");
    const auto bc = run_command({LOCUS_CLI_BIN, "import", "ipin", bad_csv, "--server", url});
    EXPECT_NE(bc.status, 0);
    EXPECT_NE(bc.err.find("BLE_Locations.csv:3: 'Lon' is not a longitude: 'eleven'; nothing imported"), std::string::npos) << bc.err;

    const std::string bad_log = copy_fixture();
    replace_line(bad_log + "/trials/IPIN2023_T3_TrainingTrial52_repetition01.txt", 9, "WIFI;4.000;1004.000;SSID;20:23:00:00:00:02;2437");
    const auto bl = run_command({LOCUS_CLI_BIN, "import", "ipin", bad_log, "--server", url});
    EXPECT_NE(bl.status, 0);
    EXPECT_NE(bl.err.find("IPIN2023_T3_TrainingTrial52_repetition01.txt:9:"), std::string::npos) << bl.err;

    const auto none = run_command({LOCUS_CLI_BIN, "import", "ipin", kFixture, "--server", url, "--trials", "*Trial99*"});
    EXPECT_NE(none.status, 0);
    EXPECT_NE(none.err.find("matches --trials"), std::string::npos) << none.err;

    // None of them reached the server.
    EXPECT_EQ(map_count(server), 0u);
}

TEST(EvalIpin, WifiBaroNamesWhatItLacks) {
    ServerProcess server{{"--quiet"}};
    const auto no_map = run_command({LOCUS_CLI_BIN, "eval", "ipin", kFixture, "--server", server.url(), "--trials", "*Trial52*", "--method",
                                     "wifi-baro", "--json"});
    EXPECT_NE(no_map.status, 0);
    EXPECT_NE(no_map.err.find("--method wifi-baro needs --map ID"), std::string::npos) << no_map.err;
    for (const char* tracker : {"pdr", "kalman", "walk_pf"}) {
        const auto r = run_command({LOCUS_CLI_BIN, "eval", "ipin", kFixture, "--server", server.url(), "--trials", "*Trial52*", "--method",
                                    tracker, "--known-start"});
        EXPECT_NE(r.status, 0);
        EXPECT_NE(r.err.find(std::string("--method ") + tracker + " needs --map ID"), std::string::npos) << r.err;
    }
    // A map whose one floor has no elevation_m: the barometer cannot place anything on it.
    const auto map = body_of(server.post("/v1/maps", {{"name", "flat"}}), 201);
    const auto b = body_of(server.post("/v1/maps/" + std::to_string(map["id"].get<std::int64_t>()) + "/buildings", {{"name", "B"}}), 201);
    body_of(server.post("/v1/buildings/" + std::to_string(b["id"].get<std::int64_t>()) + "/floors",
                        {{"name", "G"}, {"level", 0}, {"width", 200}, {"height", 100}}),
            201);
    const auto flat = run_command({LOCUS_CLI_BIN, "eval", "ipin", kFixture, "--server", server.url(), "--map",
                                   std::to_string(map["id"].get<std::int64_t>()), "--trials", "*Trial52*", "--method", "wifi-baro"});
    EXPECT_NE(flat.status, 0);
    EXPECT_NE(flat.err.find("needs the map's floors' elevation_m"), std::string::npos) << flat.err;
    const auto flat_pf = run_command({LOCUS_CLI_BIN, "eval", "ipin", kFixture, "--server", server.url(), "--map",
                                      std::to_string(map["id"].get<std::int64_t>()), "--trials", "*Trial52*", "--method", "walk_pf"});
    EXPECT_NE(flat_pf.status, 0);
    EXPECT_NE(flat_pf.err.find("--method walk_pf needs the map's floors' elevation_m"), std::string::npos) << flat_pf.err;
}

TEST(SurveyWalkCli, LandmarksFromACsvOrFromPosiThroughTheFloorsGeoreference) {
    ServerProcess server{{"--quiet"}};
    const auto map = body_of(server.post("/v1/maps", {{"name", "walks"}}), 201);
    const auto b = body_of(server.post("/v1/maps/" + std::to_string(map["id"].get<std::int64_t>()) + "/buildings", {{"name", "B"}}), 201);
    const auto f = body_of(server.post("/v1/buildings/" + std::to_string(b["id"].get<std::int64_t>()) + "/floors",
                                       {{"name", "G"}, {"level", 0}, {"width", 200}, {"height", 100}}),
                           201);
    const std::string fid = std::to_string(f["id"].get<std::int64_t>());
    const auto rm = body_of(server.post("/v1/floors/" + fid + "/radiomaps", {{"name", "walked"}}), 201);
    const std::string rmid = std::to_string(rm["id"].get<std::int64_t>());

    // POSI lat/lon need the floor's georeference.
    const auto nogeo = run_command({LOCUS_CLI_BIN, "survey", "walk", kT01, "--server", server.url(), "--radiomap", "0=" + rmid});
    EXPECT_NE(nogeo.status, 0);
    EXPECT_NE(nogeo.err.find("has no georeference"), std::string::npos) << nogeo.err;
    EXPECT_TRUE(items(server, "/v1/radiomaps/" + rmid + "/rps").empty());

    // Landmarks from a CSV in the floor's frame: T01's times, the walk moved to (10,10) → (20,10) → (20,20).
    const std::string csv = make_temp_dir() + "/landmarks.csv";
    std::ofstream(csv) << "t,floor,x,y\n10,0,10,10\n20,0,20,10\n30,0,20,20\n";
    const auto c = run_command({LOCUS_CLI_BIN, "survey", "walk", kT01, "--server", server.url(), "--radiomap", "0=" + rmid, "--landmarks",
                                csv, "--cell", "0", "--no-progress"});
    ASSERT_EQ(c.status, 0) << c.err;
    const json cj = json::parse(c.out);
    EXPECT_EQ(cj["walk"]["placed"], 11);  // 10, 12, ..., 30 s: one RP each
    EXPECT_EQ(cj["created"], 11);
    const auto rps = items(server, "/v1/radiomaps/" + rmid + "/rps");
    ASSERT_EQ(rps.size(), 11u);
    const json at16 = by_name(rps, "IPIN2023_T3_TrainingTrial01_repetition01 0m #004");  // t = 16 s
    EXPECT_DOUBLE_EQ(at16["x"].get<double>(), 16.0);
    EXPECT_DOUBLE_EQ(at16["y"].get<double>(), 10.0);

    // With the georeference the POSI lines place the walk where the fixture made it: floor
    // point (70, 40) is the data set's origin.
    body_of(server.patch("/v1/floors/" + fid, {{"geo", {{"lat", 49.46115}, {"lon", 11.11115}, {"x", 70}, {"y", 40}, {"bearing_deg", 0}}}}));
    const auto rm2 = body_of(server.post("/v1/floors/" + fid + "/radiomaps", {{"name", "walked posi"}}), 201);
    const std::string rm2id = std::to_string(rm2["id"].get<std::int64_t>());
    const auto p = run_command({LOCUS_CLI_BIN, "survey", "walk", kT01, "--server", server.url(), "--radiomap", "0=" + rm2id, "--cell", "0",
                                "--no-progress"});
    ASSERT_EQ(p.status, 0) << p.err;
    const json at16p = by_name(items(server, "/v1/radiomaps/" + rm2id + "/rps"), "IPIN2023_T3_TrainingTrial01_repetition01 0m #004");
    EXPECT_NEAR(at16p["x"].get<double>(), 76.0, 0.02);
    EXPECT_NEAR(at16p["y"].get<double>(), 40.0, 0.02);
    // Again: nothing merged twice.
    const auto p2 = run_command({LOCUS_CLI_BIN, "survey", "walk", kT01, "--server", server.url(), "--radiomap", "0=" + rm2id, "--cell", "0",
                                 "--no-progress"});
    ASSERT_EQ(p2.status, 0) << p2.err;
    EXPECT_EQ(json::parse(p2.out)["already_uploaded"], 11);

    // Bad input: a malformed landmarks line, a mapping that is not FLOOR=ID.
    std::ofstream(csv) << "t,floor,x,y\n10,0,10,10\n20,0,twenty,10\n";
    const auto bad = run_command({LOCUS_CLI_BIN, "survey", "walk", kT01, "--server", server.url(), "--radiomap", "0=" + rmid, "--landmarks", csv});
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.err.find("landmarks.csv:3: 'x' is not a finite number: 'twenty'"), std::string::npos) << bad.err;
    const auto badmap = run_command({LOCUS_CLI_BIN, "survey", "walk", kT01, "--server", server.url(), "--radiomap", "ground"});
    EXPECT_NE(badmap.status, 0);
    EXPECT_NE(badmap.err.find("expected FLOOR=ID"), std::string::npos) << badmap.err;
    EXPECT_EQ(items(server, "/v1/radiomaps/" + rmid + "/rps").size(), 11u);
}

}  // namespace
}  // namespace cli_import_ipin_test
