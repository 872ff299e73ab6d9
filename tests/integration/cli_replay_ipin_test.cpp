// `locus replay` with a GetSensorData/IPIN logfile against a real server (tools/ipin_replay.hpp),
// on the tiny folder tests/fixtures/ipin_import: T52 walks from floor 0 (POSI at 10 and 20 s)
// down the stairs to floor -2 (POSI at 40 and 50 s); its pressure rises by 0.66 hPa (5.7 m down,
// the floors' elevations) between its 24 s and 30 s samples; it has no ACCE, so no step. The
// map is the fixture's import (T01 and T52's scans).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "server_process.hpp"
#include "text_file.hpp"
#include "track_call.hpp"
#include "build_paths.hpp"

namespace cli_replay_ipin_test {
namespace {

using locus::testing::body_of;
using locus::testing::make_temp_dir;
using locus::testing::run_command;
using locus::testing::ServerProcess;
using locus::testing::track_call;
using nlohmann::json;
namespace fs = std::filesystem;

const std::string kFixture = std::string(LOCUS_TEST_FIXTURES) + "/ipin_import";
const std::string kT52 = kFixture + "/trials/IPIN2023_T3_TrainingTrial52_repetition01.txt";

struct Imported {
    ServerProcess server{{"--quiet"}};
    std::string map_id;
    Imported() {
        const auto r = run_command({LOCUS_CLI_BIN, "import", "ipin", kFixture, "--server", server.url(), "--cell", "5", "--no-progress"});
        EXPECT_EQ(r.status, 0) << r.err;
        map_id = std::to_string(json::parse(r.out)["map_id"].get<std::int64_t>());
    }
    locus::testing::CommandResult replay(std::vector<std::string> extra, const std::string& file = kT52) const {
        std::vector<std::string> cmd = {LOCUS_CLI_BIN, "replay", file, "--server", server.url(), "--map", map_id};
        cmd.insert(cmd.end(), extra.begin(), extra.end());
        return run_command(cmd);
    }
};

// The file's lines without those starting with `tag`.
std::string without_tag(const std::string& path, const std::string& tag) {
    std::ifstream in(path);
    std::string all, line;
    while (std::getline(in, line))
        if (line.rfind(tag, 0) != 0) all += line + "\n";
    const std::string out = make_temp_dir() + "/no_" + tag + ".txt";
    std::ofstream(out) << all;
    return out;
}

TEST(ReplayIpin, TheTrackersAndTheServersAnswersScoreTheWalkOnBothFloors) {
    const Imported s;
    for (const char* rule : {"walk_pf", "kalman", "pdr", "wifi"}) {
        const auto r = s.replay({"--rule", rule});
        ASSERT_EQ(r.status, 0) << rule << ": " << r.err;
        const json out = json::parse(r.out);
        EXPECT_EQ(out["format"], "ipin") << rule;
        EXPECT_EQ(out["rule"], rule);
        EXPECT_EQ(out["phone"], "SM-G930F");
        EXPECT_EQ(out["landmarks"], 4);
        ASSERT_FALSE(out["estimates"].empty()) << rule;
        const json& first = out["estimates"][0];
        // The venue's frame and WGS84 together: (70, 40) is the frame's origin, 49.46115 N 11.11115 E.
        EXPECT_NEAR(first["lat"].get<double>(), 49.46115, 0.001) << rule;
        EXPECT_NEAR(first["lon"].get<double>(), 11.11115, 0.001) << rule;
        EXPECT_EQ(out["score"]["n"], 4) << rule;
        EXPECT_EQ(out["score"]["unscored"], 0) << rule;
    }
    // The trackers' floor is the barometer's: both landmarks after the stairs are on -2.
    const json pf = json::parse(s.replay({}).out);
    EXPECT_EQ(pf["rule"], "walk_pf");  // the default: the live track, what a phone gets
    EXPECT_TRUE(pf.contains("track")) << pf.dump();
    EXPECT_EQ(pf["score"]["floor_hit_rate"], 1.0);
    int below = 0;
    for (const auto& e : pf["estimates"])
        if (e["t"].get<double>() >= 40.0) below += e["floor"] == -2 ? 1 : -1000;
    EXPECT_GT(below, 0);
}

TEST(ReplayIpin, TheThinClientPathRunsTheServersFilterOnALiveTrack) {
    const Imported s;
    const auto r = s.replay({"--rule", "thin"});
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    ASSERT_TRUE(out.contains("track")) << out.dump();
    // One request per scan (9 scans), and one for the pressure sample after the last.
    EXPECT_GE(out["requests"].get<int>(), 10);
    ASSERT_FALSE(out["estimates"].empty());
    EXPECT_EQ(out["score"]["n"], 4);
    // The server's barometric floor (docs/tracks.md): floor -2 after the stairs.
    EXPECT_EQ(out["score"]["floor_hit_rate"], 1.0) << out["score"].dump();
    // The fused fixes are the live track's, stored and closed.
    const json track =
        body_of(track_call(s.server, "GET", "/v1/tracks/" + out["track"]["id"].dump(), {out["track"]["token"].get<std::string>()}));
    EXPECT_EQ(track["state"], "closed");
    EXPECT_EQ(track["fixes"].get<std::size_t>(), out["estimates"].size());
    EXPECT_TRUE(out.contains("rss_offset_db"));

    // With the first landmark given, the track starts there.
    const json known = json::parse(s.replay({"--rule", "thin", "--known-start"}).out);
    ASSERT_FALSE(known["estimates"].empty());
    EXPECT_NEAR(known["estimates"][0]["t"].get<double>(), 10.0, 1e-3);
    // (the walk filter's cloud drawn round a fix of σ 0.5 m: its mode within a few decimetres)
    EXPECT_NEAR(known["estimates"][0]["x"].get<double>(), 70.0, 0.5);
    EXPECT_NEAR(known["estimates"][0]["y"].get<double>(), 40.0, 0.5);
    EXPECT_EQ(known["estimates"][0]["floor"], 0);

    // Other settings: the track is opened with the options given, and keeps them.
    const auto own = s.replay({"--rule", "thin", "--fusion-options", R"({"step_scale": 1.2, "fix_sigma_m": 4})"});
    ASSERT_EQ(own.status, 0) << own.err;
    const json mine = json::parse(own.out);
    const json expected = {{"step_scale", 1.2}, {"fix_sigma_m", 4}};
    EXPECT_EQ(mine["fusion_options"], expected);
    const json opened =
        body_of(track_call(s.server, "GET", "/v1/tracks/" + mine["track"]["id"].dump(), {mine["track"]["token"].get<std::string>()}));
    EXPECT_EQ(opened["fusion_options"], expected);
}

// The log with a strong reading of beacon BLE1 (the import's, floor 0) every second from 20 s
// to 30 s, while the walker is on floor 0 (each line in its place: the app writes one clock in order).
std::string with_beacon_readings(const std::string& path) {
    std::ifstream in(path);
    std::string all, line;
    int next = 20;
    const auto readings_until = [&](double t) {
        for (; next <= 30 && next <= t; ++next)
            all += "BLE4;" + std::to_string(next) + ".000;iBeacon;BE:AC:20:23:00:01;-55;-59;1;1;11111111-1111-BEAC-2023-111111111111\n";
    };
    while (std::getline(in, line)) {
        const auto semi = line.find(';');
        if (line.empty() || line[0] == '%' || semi == std::string::npos) {
            all += line + "\n";
            continue;
        }
        readings_until(std::stod(line.substr(semi + 1)));
        all += line + "\n";
    }
    readings_until(1e9);
    const std::string out = make_temp_dir() + "/ble.txt";
    std::ofstream(out) << all;
    return out;
}

TEST(ReplayIpin, TheLogsBeaconReadingsReachTheLiveTrack) {
    // Two servers with the same import: each replay's track is the first, so both filters draw
    // the same random numbers (a track is seeded with its id) and only the beacons differ.
    const Imported a, b;
    const std::string file = with_beacon_readings(kT52);
    const json with = json::parse(a.replay({}, file).out), without = json::parse(b.replay({"--no-ble"}, file).out);
    ASSERT_EQ(with["track"]["id"], without["track"]["id"]);
    // BLE1 as the import placed it (BLE_Locations.csv): each reading counted is a fix there, so
    // from 20 s on the track is drawn towards it; before, nothing differs.
    const double lat = 49.4611949564836, lon = 11.1112189713338;
    const auto off = [&](const json& e) { return std::hypot(e["lat"].get<double>() - lat, (e["lon"].get<double>() - lon) * 0.65); };
    double off_with = 0.0, off_without = 0.0;
    std::size_t before = 0, during = 0;
    for (const auto& e : with["estimates"]) {
        const double t = e["t"].get<double>();
        if (t < 20.0) ++before;
        if (t >= 20.0 && t <= 31.0) {
            off_with += off(e);
            ++during;
        }
    }
    for (const auto& e : without["estimates"]) {
        const double t = e["t"].get<double>();
        if (t >= 20.0 && t <= 31.0) off_without += off(e);
    }
    ASSERT_GT(before, 0u);
    for (std::size_t i = 0; i < before; ++i) EXPECT_EQ(with["estimates"][i], without["estimates"][i]);
    // Six fixes (one per beacon per 2 s) answer fused fixes of their own.
    EXPECT_EQ(with["estimates"].size(), without["estimates"].size() + 6);
    ASSERT_GT(during, 6u);
    EXPECT_LT(off_with / during, 0.9 * off_without / (during - 6)) << with["estimates"].dump();
}

TEST(ReplayIpin, ALogWithoutPosiReplaysUnscored) {
    const Imported s;
    const std::string no_posi = without_tag(kT52, "POSI");
    for (const char* rule : {"walk_pf", "thin"}) {
        const auto r = s.replay({"--rule", rule}, no_posi);
        ASSERT_EQ(r.status, 0) << rule << ": " << r.err;
        const json out = json::parse(r.out);
        EXPECT_EQ(out["landmarks"], 0);
        EXPECT_FALSE(out.contains("score")) << rule;
        EXPECT_FALSE(out["estimates"].empty()) << rule;
    }
}

TEST(ReplayIpin, BadInputIsRefusedByName) {
    const Imported s;
    const auto no_map = run_command({LOCUS_CLI_BIN, "replay", kT52, "--server", s.server.url()});
    EXPECT_NE(no_map.status, 0);
    EXPECT_NE(no_map.err.find("a logfile replays against a map: --map ID"), std::string::npos) << no_map.err;
    const auto radiomap = run_command({LOCUS_CLI_BIN, "replay", kT52, "--server", s.server.url(), "--radiomap", "1", "--map", s.map_id});
    EXPECT_NE(radiomap.status, 0);
    EXPECT_NE(radiomap.err.find("--radiomap is for a walk file"), std::string::npos) << radiomap.err;
    const auto rule = s.replay({"--rule", "midpoint"});
    EXPECT_NE(rule.status, 0);
    EXPECT_NE(rule.err.find("unknown --rule 'midpoint' for a logfile"), std::string::npos) << rule.err;
    const auto live = s.replay({"--live", s.server.url(), "--live-map", s.map_id});
    EXPECT_NE(live.status, 0);
    EXPECT_NE(live.err.find("--live and --upload-survey take walk files"), std::string::npos) << live.err;
    const auto no_floor = run_command({LOCUS_CLI_BIN, "replay", kT52, "--server", s.server.url(), "--map", "999"});
    EXPECT_NE(no_floor.status, 0);
    // --fusion-options: a JSON object, each option checked by the server, which names it.
    const auto not_json = s.replay({"--rule", "thin", "--fusion-options", "step_scale=1"});
    EXPECT_NE(not_json.status, 0);
    EXPECT_NE(not_json.err.find("--fusion-options takes a JSON object"), std::string::npos) << not_json.err;
    const auto out_of_range = s.replay({"--rule", "thin", "--fusion-options", R"({"step_scale": 9})"});
    EXPECT_NE(out_of_range.status, 0);
    EXPECT_NE(out_of_range.err.find("fusion_options.step_scale"), std::string::npos) << out_of_range.err;
    const auto both = s.replay({"--rule", "thin", "--server-defaults", "--fusion-options", "{}"});
    EXPECT_NE(both.status, 0);
    // walk_pf's live track learns its phone's offset itself; only it takes fusion_options.
    const auto no_offset = s.replay({"--no-offset"});
    EXPECT_NE(no_offset.status, 0);
    EXPECT_NE(no_offset.err.find("--no-offset is for kalman and pdr"), std::string::npos) << no_offset.err;
    const auto kalman_options = s.replay({"--rule", "kalman", "--fusion-options", "{}"});
    EXPECT_NE(kalman_options.status, 0);
    EXPECT_NE(kalman_options.err.find("--fusion-options opens walk_pf's live track"), std::string::npos) << kalman_options.err;

    // A malformed line is named by file and line; nothing is posted.
    const std::string dir = make_temp_dir();
    const std::string bad = dir + "/bad.txt";
    fs::copy_file(kT52, bad);
    {
        std::ifstream in(bad);
        std::string all, line;
        for (int n = 1; std::getline(in, line); ++n) all += (n == 10 ? std::string("WIFI;4.000;1004.000;SSID;20:23:00:00:00:02;2437") : line) + "\n";
        std::ofstream(bad) << all;
    }
    const auto b = s.replay({"--rule", "thin"}, bad);
    EXPECT_NE(b.status, 0);
    EXPECT_NE(b.err.find("bad.txt:10"), std::string::npos) << b.err;
    EXPECT_TRUE(b.out.empty()) << b.out;
    // A walk file's --map is refused too.
    const std::string walk = dir + "/walk.json";
    std::ofstream(walk) << "{}";
    const auto w = run_command({LOCUS_CLI_BIN, "replay", walk, "--server", s.server.url(), "--map", s.map_id});
    EXPECT_NE(w.status, 0);
    EXPECT_NE(w.err.find("--map is for a logfile"), std::string::npos) << w.err;
}

}  // namespace
}  // namespace cli_replay_ipin_test
