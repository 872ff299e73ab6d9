// `locus eval calibration` end to end on a synthetic UJIIndoorLoc survey whose APs follow the
// log-distance model exactly: the fits explain the RSS, the modelled maps localize held-out
// rows nearly as well as the surveyed one; and bad arguments are refused with a reason.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace eval_calibration_test {
namespace {

using locus::testing::run_command;
using nlohmann::json;

// One floor of 30 m × 20 m, RPs every 2.5 m with 3 scans each (user 1) and every RP again
// with one scan by user 2 (the held-out one). Four APs, positions known only to this file.
std::string write_survey() {
    const std::string path = std::filesystem::temp_directory_path() / ("locus-calibration-" + std::to_string(::getpid()) + ".csv");
    std::ofstream out(path);
    out << "WAP001,WAP002,WAP003,WAP004,LONGITUDE,LATITUDE,FLOOR,BUILDINGID,SPACEID,RELATIVEPOSITION,USERID,PHONEID,"
           "TIMESTAMP\n";
    const double ap[4][4] = {{3, 4, -38, 2.2}, {27, 5, -42, 2.6}, {15, 17, -40, 2.0}, {8, 15, -45, 3.0}};
    long long ts = 1000;
    for (double x = 1.25; x < 30; x += 2.5)
        for (double y = 1.25; y < 20; y += 2.5)
            for (int scan = 0; scan < 4; ++scan) {
                for (const auto& a : ap) {
                    const double d = std::max(1.0, std::hypot(x - a[0], y - a[1]));
                    const double rss = std::round(a[2] - 10.0 * a[3] * std::log10(d) + (scan % 2 ? 1 : -1));
                    out << (rss < -100 ? 100.0 : rss) << ",";
                }
                out << x << "," << y << ",0,0,0,1," << (scan < 3 ? 1 : 2) << ",1," << ts++ << "\n";
            }
    return path;
}

TEST(EvalCalibration, FitsExplainAModelledSurveyAndItsMapsLocalize) {
    const std::string survey = write_survey();
    const auto r = run_command({LOCUS_CLI_BIN, "eval", "calibration", "--train", survey, "--holdout-user", "2", "--json",
                                "--min-rss", "-100"});
    std::filesystem::remove(survey);
    ASSERT_EQ(r.status, 0) << r.err;
    const json out = json::parse(r.out);
    ASSERT_EQ(out.at("fits").size(), 1u);
    EXPECT_EQ(out["fits"][0].at("models"), 4);
    EXPECT_GT(out["fits"][0].at("median_r2").get<double>(), 0.95);
    std::map<std::string, json> maps;
    for (const auto& m : out.at("maps")) maps[m.at("map")] = m;
    ASSERT_EQ(maps.size(), 3u);
    // Held-out rows are on the RPs: the surveyed map finds them within a grid step, and a map
    // modelled from good fits at the same positions does nearly as well.
    EXPECT_LT(maps["surveyed"].at("mean_error_m").get<double>(), 2.5);
    EXPECT_LT(maps["model_rps"].at("mean_error_m").get<double>(), 3.5);
    EXPECT_LT(maps["model_grid"].at("mean_error_m").get<double>(), 4.0);
    EXPECT_EQ(maps["surveyed"].at("rps"), 12 * 8);
    EXPECT_EQ(maps["model_rps"].at("rps"), 12 * 8);  // every RP hears some modelled AP
    EXPECT_EQ(maps["model_grid"].at("rps"), 9 * 6);  // 3 m cells centred inside the 27.5 m × 17.5 m the RPs span
}

TEST(EvalCalibration, BadArgumentsAreRefusedWithAReason) {
    const std::string survey = write_survey();
    const auto both = run_command({LOCUS_CLI_BIN, "eval", "calibration", "--train", survey, "--holdout-user", "2", "--holdout-phone", "1"});
    EXPECT_NE(both.status, 0);
    EXPECT_NE(both.err.find("exactly one of"), std::string::npos) << both.err;
    const auto few = run_command({LOCUS_CLI_BIN, "eval", "calibration", "--train", survey, "--holdout-user", "2", "--min-rps", "2"});
    EXPECT_NE(few.status, 0);
    EXPECT_NE(few.err.find("--min-rps"), std::string::npos) << few.err;
    const auto nobody = run_command({LOCUS_CLI_BIN, "eval", "calibration", "--train", survey, "--holdout-user", "9"});
    EXPECT_NE(nobody.status, 0);
    EXPECT_NE(nobody.err.find("no training or no test rows"), std::string::npos) << nobody.err;
    const auto step = run_command({LOCUS_CLI_BIN, "eval", "calibration", "--train", survey, "--holdout-user", "2", "--step", "0"});
    EXPECT_NE(step.status, 0);
    EXPECT_NE(step.err.find("--step"), std::string::npos) << step.err;
    std::filesystem::remove(survey);
}

}  // namespace
}  // namespace eval_calibration_test
