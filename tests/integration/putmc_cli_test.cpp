// `locus import putmc` and `locus eval walks` against the real server, on the tiny PUTMC
// fixture (tests/fixtures/putmc: 4 survey points, a 305 × 105 px drawing, 11 s of walk 1
// with its first 3 scans).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <stdexcept>

#include "server_process.hpp"
#include "track_call.hpp"
#include "build_paths.hpp"

namespace putmc_cli_test {
namespace {

using locus::testing::body_of;
using locus::testing::run_command;
using locus::testing::ServerProcess;
using locus::testing::track_call;
using nlohmann::json;

const std::string kFixture = std::string(LOCUS_TEST_FIXTURES) + "/putmc";

json run_ok(const std::vector<std::string>& argv) {
    const auto r = run_command(argv);
    if (r.status != 0) throw std::runtime_error("exit status " + std::to_string(r.status) + ":\n" + r.err);
    return json::parse(r.out);
}

json import_fixture(const ServerProcess& server) {
    return run_ok({LOCUS_CLI_BIN, "import", "putmc", "--server", server.url(), "--map", "PUTMC", "--no-progress", kFixture});
}

TEST(ImportPutmc, FloorImagePlanAndRpsOnceEach) {
    ServerProcess server{{"--quiet"}};
    const json first = import_fixture(server);
    EXPECT_EQ(first["rps"], 4);
    EXPECT_EQ(first["created"], 4);
    EXPECT_EQ(first["scans"], 4);
    const double height = 105 / 2.83988631094;
    const auto floor = body_of(server.get("/v1/floors/" + std::to_string(first["floor_id"].get<int>())));
    EXPECT_NEAR(floor["width"].get<double>(), 305 / 2.83988631094, 1e-6);
    EXPECT_NEAR(floor["height"].get<double>(), height, 1e-6);
    const auto placement = body_of(server.get("/v1/floors/" + std::to_string(first["floor_id"].get<int>()) + "/image/placement"));
    EXPECT_EQ(placement["width_px"], 305);
    EXPECT_NEAR(placement["metres_per_pixel"].get<double>(), 1 / 2.83988631094, 1e-9);
    // The plan made from the drawing is on the floor (its outline is a wall).
    EXPECT_EQ(server.get("/v1/floors/" + std::to_string(first["floor_id"].get<int>()) + "/plan").status, 200);
    // RP p1 at the survey's (30.417, 20.293), y flipped to run up the floor.
    const auto rps = body_of(server.get("/v1/radiomaps/" + std::to_string(first["radiomap_id"].get<int>()) + "/rps"))["items"];
    ASSERT_EQ(rps.size(), 4u);
    bool found = false;
    for (const auto& rp : rps)
        if (rp["name"] == "p1") {
            found = true;
            EXPECT_NEAR(rp["x"].get<double>(), 30.4172467139, 1e-6);
            EXPECT_NEAR(rp["y"].get<double>(), height - 20.2929559505, 1e-6);
        }
    EXPECT_TRUE(found);

    const json again = import_fixture(server);
    EXPECT_EQ(again["already_uploaded"], 4);
    EXPECT_EQ(again["created"], 0);
    EXPECT_EQ(again["floor_id"], first["floor_id"]);
    EXPECT_EQ(again["radiomap_id"], first["radiomap_id"]);
}

TEST(ImportPutmc, RefusesADirectoryWithoutTheSurvey) {
    ServerProcess server{{"--quiet"}};
    const auto r = run_command({LOCUS_CLI_BIN, "import", "putmc", "--server", server.url(), "--no-progress", kFixture + "/trajs"});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("neither map/wifi.map"), std::string::npos) << r.err;
}

TEST(EvalWalks, EveryMethodAtEveryScanThroughTheServer) {
    ServerProcess server{{"--quiet"}};
    const json imported = import_fixture(server);
    const std::string rm = std::to_string(imported["radiomap_id"].get<int>());
    const json out = run_ok({LOCUS_CLI_BIN, "eval", "walks", "--server", server.url(), "--radiomap", rm, "--json", "--smooth", kFixture});
    ASSERT_EQ(out["walks"].size(), 1u);
    const auto& w = out["walks"][0];
    EXPECT_EQ(w["walk"], "tiny_walk");
    EXPECT_EQ(w["scans"], 3);
    EXPECT_EQ(w["fixes"], 3);  // the walk's scans hear the survey's APs
    for (const char* m : {"wifi", "pdr", "only_wifi", "midpoint", "midpoint_threshold", "proportional", "proportional2",
                          "midpoint_tuned", "midpoint_threshold_tuned", "proportional_tuned", "proportional2_tuned",
                          "kalman", "particle", "walk_pf_local", "walk_pf", "rts_smoother", "pf_smoother"}) {
        ASSERT_TRUE(out["pooled"].contains(m)) << m;
        EXPECT_EQ(out["pooled"][m]["n"], 3) << m;
        EXPECT_GE(out["pooled"][m]["mean_m"].get<double>(), 0.0) << m;
    }
    // wifi's error at each scan is the server's fix against the flipped truth: recomputed here.
    const auto& fixes = w["methods"]["wifi"]["at_scans"];
    double sum = 0.0;
    for (int i = 0; i < 3; ++i)
        sum += std::hypot(fixes[i][0].get<double>() - w["truth"][i][0].get<double>(),
                          fixes[i][1].get<double>() - w["truth"][i][1].get<double>());
    EXPECT_NEAR(out["pooled"]["wifi"]["mean_m"].get<double>(), sum / 3, 1e-9);
    EXPECT_NEAR(w["truth"][2][1].get<double>(), 105 / 2.83988631094 - 22.48080166395504, 1e-9);

    // walk_pf is the server's own live track of the walk: one track per walk, closed, holding
    // the fused fix eval walks scored at each scan.
    ASSERT_TRUE(w.contains("live_track")) << w.dump();
    const json track = body_of(
        track_call(server, "GET", "/v1/tracks/" + w["live_track"]["id"].dump(), {w["live_track"]["token"].get<std::string>()}));
    EXPECT_EQ(track["state"], "closed");
    EXPECT_EQ(track["label"], "eval walks tiny_walk");
    const json& last = w["methods"]["walk_pf"]["at_scans"][2];
    EXPECT_NEAR(track["latest"]["x"].get<double>(), last[0].get<double>(), 1e-9);
    EXPECT_NEAR(track["latest"]["y"].get<double>(), last[1].get<double>(), 1e-9);

    // The live track's own scan fixes, scored beside it; its track matched them in its subarea.
    ASSERT_TRUE(out["pooled"].contains("walk_pf.scan_fixes")) << out["pooled"].dump();
    EXPECT_EQ(out["pooled"]["walk_pf.scan_fixes"]["n"], 3);
    EXPECT_FALSE(track.contains("fusion_options")) << track.dump();

    // One method, as a table, with the scan fixes' row; --no-subarea opens the tracks without it.
    const auto r = run_command({LOCUS_CLI_BIN, "eval", "walks", "--server", server.url(), "--radiomap", rm, "--method", "walk_pf", kFixture});
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("pooled (1 walks)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("walk_pf.scan_fixes"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("kalman"), std::string::npos) << r.out;
    const json off = run_ok({LOCUS_CLI_BIN, "eval", "walks", "--server", server.url(), "--radiomap", rm, "--method", "walk_pf", "--no-subarea", "--json", kFixture});
    const json& ow = off["walks"][0];
    const json opened = body_of(track_call(server, "GET", "/v1/tracks/" + ow["live_track"]["id"].dump(), {ow["live_track"]["token"].get<std::string>()}));
    EXPECT_EQ(opened["fusion_options"], json({{"subarea", false}})) << opened.dump();
    EXPECT_EQ(off["pooled"]["walk_pf.scan_fixes"]["n"], 3);
}

TEST(EvalWalks, BadInputIsNamed) {
    ServerProcess server{{"--quiet"}};
    const json imported = import_fixture(server);
    const std::string rm = std::to_string(imported["radiomap_id"].get<int>());
    auto r = run_command({LOCUS_CLI_BIN, "eval", "walks", "--server", server.url(), "--radiomap", rm, "--method", "nope", kFixture});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("unknown --method 'nope'"), std::string::npos) << r.err;
    r = run_command({LOCUS_CLI_BIN, "eval", "walks", "--server", server.url(), "--radiomap", rm, kFixture + "/map"});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("no walk under"), std::string::npos) << r.err;
    // A truncated wifi.map: the error names the file and line.
    const auto dir = std::filesystem::temp_directory_path() / ("putmc_bad_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (const char* f : {"acc.map", "orient.map", "positions.map"})
        std::filesystem::copy_file(kFixture + "/trajs/tiny_walk/" + f, dir / f, std::filesystem::copy_options::overwrite_existing);
    {
        std::ofstream(dir / "wifi.map") << "484328393044 0 3\n64:66:b3:be:99:53\tVision\t-89.0 2462 19668092087\n";
    }
    r = run_command({LOCUS_CLI_BIN, "eval", "walks", "--server", server.url(), "--radiomap", rm, dir.string()});
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("wifi.map:1: truncated"), std::string::npos) << r.err;
    std::filesystem::remove_all(dir);
}

// The rest of the bad-input target end to end: unsorted timestamps and NaN samples are errors
// naming the file and line; a walk none of whose scans localizes (here: it has no scan) is
// skipped with a note, and the other walks are still scored.
TEST(EvalWalks, UnsortedAndNanSamplesAreNamedAndAWalkWithoutScansIsSkipped) {
    ServerProcess server{{"--quiet"}};
    const json imported = import_fixture(server);
    const std::string rm = std::to_string(imported["radiomap_id"].get<int>());
    namespace fs = std::filesystem;
    const fs::path root = fs::temp_directory_path() / ("putmc_bad2_" + std::to_string(::getpid()));
    const fs::path tiny = kFixture + "/trajs/tiny_walk";
    const auto copy_walk = [&](const std::string& name) {
        fs::create_directories(root / name);
        for (const char* f : {"acc.map", "orient.map", "wifi.map", "positions.map"})
            fs::copy_file(tiny / f, root / name / f, fs::copy_options::overwrite_existing);
        return root / name;
    };
    const auto eval = [&](const fs::path& dir) {
        return run_command({LOCUS_CLI_BIN, "eval", "walks", "--server", server.url(), "--radiomap", rm, "--method", "walk_pf", dir.string()});
    };

    // acc.map with its 3rd sample moved before the 2nd.
    const fs::path unsorted = copy_walk("unsorted");
    {
        std::ifstream in(tiny / "acc.map");
        std::vector<std::string> lines;
        for (std::string l; std::getline(in, l);) lines.push_back(l);
        std::swap(lines[1], lines[2]);
        std::ofstream out(unsorted / "acc.map");
        for (const auto& l : lines) out << l << "\n";
    }
    auto r = eval(unsorted);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("acc.map:3: timestamp goes back"), std::string::npos) << r.err;

    // orient.map with a NaN in its 2nd sample.
    const fs::path nan = copy_walk("nan");
    {
        std::ifstream in(tiny / "orient.map");
        std::vector<std::string> lines;
        for (std::string l; std::getline(in, l);) lines.push_back(l);
        lines[1] = lines[1].substr(0, lines[1].find(' ')) + " nan 0.0 0.0 1.0 0.17";
        std::ofstream out(nan / "orient.map");
        for (const auto& l : lines) out << l << "\n";
    }
    r = eval(nan);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("orient.map:2:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not finite"), std::string::npos) << r.err;

    // A walk with no scan beside a good one: skipped with a note, the good one scored.
    fs::remove_all(root);
    copy_walk("good");
    const fs::path empty = copy_walk("no_scans");
    std::ofstream(empty / "wifi.map", std::ios::trunc).flush();
    r = eval(root);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("no_scans: no scan localized"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("pooled (2 walks)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("walk_pf                         3"), std::string::npos) << r.out;  // the good walk's 3 scans
    fs::remove_all(root);
}

}  // namespace
}  // namespace putmc_cli_test
