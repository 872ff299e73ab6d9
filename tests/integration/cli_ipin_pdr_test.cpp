// `locus pdr steps` and `locus pdr track` on a GetSensorData / IPIN logfile: 10 s of the IPIN
// 2023 walk T21 repetition 01 (Samsung S7; tests/fixtures/ipin/README.md), read by its format
// and fed to the same step detector as the accelerometer CSV.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "server_process.hpp"
#include "text_file.hpp"
#include "build_paths.hpp"

namespace cli_ipin_pdr_test {
namespace {

using locus::testing::contains;
using locus::testing::make_temp_dir;
using locus::testing::run_command;
using nlohmann::json;

const std::string kLog = std::string(LOCUS_TEST_FIXTURES) + "/ipin/T21_rep01_10s.txt";

std::vector<std::string> fields(const std::string& line) {
    std::vector<std::string> f;
    std::stringstream s(line);
    std::string x;
    while (std::getline(s, x, ';')) f.push_back(x);
    return f;
}

TEST(PdrIpinLog, StepsMatchTheSameAccelerometerAsCsv) {
    const auto r = run_command({LOCUS_CLI_BIN, "pdr", "steps", "--times", kLog});
    ASSERT_EQ(r.status, 0) << r.err;
    const json j = json::parse(r.out);
    EXPECT_EQ(j["format"], "ipin");
    // 10 s of walking at a normal cadence (1.5–2.2 steps/s), less the detector's start-up.
    EXPECT_GE(j["steps"].get<int>(), 5);
    EXPECT_LE(j["steps"].get<int>(), 23);
    EXPECT_NEAR(j["duration_s"].get<double>(), 10.0, 0.1);
    // The fixture holds POSI 2 (65.9817 s) and 3 (70.4974 s).
    EXPECT_NEAR(j["posi_span_s"].get<double>(), 70.4974 - 65.9817, 1e-9);
    long in_span = 0;
    for (const auto& t : j["step_times_s"]) in_span += t.get<double>() >= 65.9817 && t.get<double>() <= 70.4974;
    EXPECT_EQ(j["steps_in_posi_span"].get<long>(), in_span);

    // The ACCE lines as the CSV `t,ax,ay,az`, on the clock docs/ipin.md describes (the sensor
    // timestamp moved by the smallest App − Sensor): the same steps at the same times.
    std::ifstream in(kLog);
    std::string line;
    std::vector<std::vector<std::string>> acce;
    double shift = std::numeric_limits<double>::infinity();
    while (std::getline(in, line))
        if (line.rfind("ACCE;", 0) == 0) {
            acce.push_back(fields(line));
            shift = std::min(shift, std::stod(acce.back()[1]) - std::stod(acce.back()[2]));
        }
    ASSERT_GT(acce.size(), 400u);
    const std::string csv = make_temp_dir() + "/acc.csv";
    {
        std::ofstream out(csv);
        out.precision(17);
        out << "t,ax,ay,az\n";
        for (const auto& f : acce) out << std::stod(f[2]) + shift << "," << f[3] << "," << f[4] << "," << f[5] << "\n";
    }
    const auto c = run_command({LOCUS_CLI_BIN, "pdr", "steps", "--times", csv});
    ASSERT_EQ(c.status, 0) << c.err;
    const json k = json::parse(c.out);
    EXPECT_EQ(k["steps"], j["steps"]);
    ASSERT_EQ(k["step_times_s"].size(), j["step_times_s"].size());
    for (std::size_t i = 0; i < k["step_times_s"].size(); ++i)
        EXPECT_NEAR(k["step_times_s"][i].get<double>(), j["step_times_s"][i].get<double>(), 1e-6);
    EXPECT_FALSE(k.contains("format"));
}

TEST(PdrIpinLog, TrackTurnsWithTheGyroscope) {
    const auto r = run_command({LOCUS_CLI_BIN, "pdr", "track", kLog});
    ASSERT_EQ(r.status, 0) << r.err;
    std::istringstream lines(r.out);
    std::string line;
    std::getline(lines, line);
    EXPECT_EQ(line.rfind("t,x,y,heading_deg,", 0), 0u) << line;
    std::vector<double> headings;
    while (std::getline(lines, line)) {
        std::stringstream s(line);
        std::string t, x, y, h;
        std::getline(s, t, ',');
        std::getline(s, x, ',');
        std::getline(s, y, ',');
        std::getline(s, h, ',');
        headings.push_back(std::stod(h));
    }
    EXPECT_GE(headings.size(), 5u);
    // With GYRO and MAGN in the log the heading is estimated, not held at the start heading.
    EXPECT_TRUE(std::any_of(headings.begin(), headings.end(), [](double h) { return std::abs(h) > 1.0; }));
}

TEST(PdrIpinLog, AMalformedLogfileNamesFileAndLine) {
    const std::string dir = make_temp_dir();
    const std::string bad = dir + "/bad.txt";
    {
        std::ofstream out(bad);
        out << "% Model: \tSM-G930F\nACCE;1.0;2.0;0;0;9.8;3\nACCE;1.02;2.02;0;nan;9.8;3\n";
    }
    for (const char* cmd : {"steps", "track"}) {
        const auto r = run_command({LOCUS_CLI_BIN, "pdr", cmd, bad});
        EXPECT_NE(r.status, 0) << cmd;
        EXPECT_TRUE(contains(r.err, bad + ":3: y is not finite")) << cmd << ": " << r.err;
    }
    const std::string no_acce = dir + "/no_acce.txt";
    {
        std::ofstream out(no_acce);
        out << "% Model: \tSM-G930F\nPRES;1.0;2.0;976.2;3\n";
    }
    const auto r = run_command({LOCUS_CLI_BIN, "pdr", "steps", no_acce});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "no ACCE lines")) << r.err;
}

}  // namespace
}  // namespace cli_ipin_pdr_test
