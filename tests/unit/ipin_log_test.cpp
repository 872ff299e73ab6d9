// The GetSensorData / IPIN logfile reader (datasets/ipin_log.*) on hand-written snippets, and
// on the IPIN 2023 Track 3 walks when LOCUS_DATA_DIR/ipin2023 is present: there the checks
// are the facts ../shared/data/ipin2023/README.md states (phones, floors, landmarks, rates).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "datasets/ipin_log.hpp"
#include "build_paths.hpp"

namespace ipin_log_test {
namespace {

namespace ipin = locus::datasets::ipin;

// One line of every tag the app's format header documents, values chosen to be told apart.
const std::string kAllTags =
    "% LogFile created by the 'GetSensorData' App for Android.\n"
    "% Date of creation: Wed Jun 14 10:00:58 GMT+02:00 2023\n"
    "% Version 2.21 July 2021\n"
    "% Manufacturer:            \tsamsung\n"
    "% Model:                   \tSM-A520F\n"
    "% API Android version:     \t26\n"
    "% Android version Release: \t8.0.0\n"
    "% Magnetometer data:  \t'MAGN;AppTimestamp(s);SensorTimestamp(s);Mag_X(uT);;Mag_Y(uT);Mag_Z(uT);Accuracy(integer)'\n"
    "\n"
    "MAGN;0.0527;65093.5402;-2.10000;-34.14000;-45.42000;0\n"
    "GYRO;0.0536;65093.5461;-0.78496;-0.53878;0.09835;3\n"
    "ACCE;0.0542;65093.5471;-1.01514;8.26000;6.21535;3\n"
    "AHRS;0.0547;65093.5471;49.975651;11.576796;-16.530445;0.42904782;0.03004867;-0.08747417;2\n"
    "SOUN;0.0676;3093.40;0.09441;73.48\n"
    "PRES;0.1198;65093.6620;976.2273;3\n"
    "LIGH;0.1220;65093.6677;349.0;1\n"
    "PROX;0.1300;65093.7000;8.0;3\n"
    "HUMI;0.1400;65093.7100;41.5;3\n"
    "TEMP;0.1500;65093.7200;23.25;3\n"
    "WIFI;0.651;65094.18;SSID2023_0001;20:23:00:00:00:01;2437;-60\n"
    "WIFI;0.651;65094.1801;SSID2023_0004;20:23:00:00:00:AB;5500;-87\n"
    "GNSS;0.9633;1686729678.0000;49.461269;11.111049;346.000;79.500;9.0;0.1;22;19\n"
    "BLE4;2.8313;iBeacon;BE:AC:20:23:00:01;-90;-59;1;6;11111111-1111-BEAC-2023-111111111111\n"
    "BLUE;3.0;my phone;AA:BB:CC:DD:EE:0F;-71\n"
    "RFID;3.5;2;1234567;-60.5;-70\n"
    "IMUX;4.0;100.5;17;0.1;0.2;9.8;0.01;0.02;0.03;20;21;22;1;2;3;0.9;0.1;0.2;0.3;1013.5;24.5\n"
    "IMUL;4.1;100.6;18;0.1;0.2;9.7;0.01;0.02;0.03;20;21;22;1;2;3;0.9;0.1;0.2;0.3;1013.4;24.4\n"
    "IMUI;4.2;5;3;0.5;0.25;0;12.5;1;2;3;4;5;6;7;8;9;10\n"
    "POSI;61.4235;1;49.461316433032;11.110964442580;-2;100\n";

std::string crlf(const std::string& s) {
    std::string out;
    for (char c : s) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
    return out;
}

// The LogError a parse raises ("" and line -1 when none).
struct Failure {
    std::string what, file;
    long line = -1;
};
Failure failure_of(const std::string& text, const std::string& file = "walk.txt") {
    try {
        ipin::parse_log(text, file);
    } catch (const ipin::LogError& e) {
        return {e.what(), e.file(), e.line()};
    }
    return {};
}

TEST(IpinLog, ReadsEveryTagWithItsValues) {
    const auto log = ipin::parse_log(kAllTags, "all.txt");
    EXPECT_EQ(log.file, "all.txt");
    EXPECT_EQ(log.header.created, "Wed Jun 14 10:00:58 GMT+02:00 2023");
    EXPECT_EQ(log.header.app_version, "2.21 July 2021");
    EXPECT_EQ(log.header.manufacturer, "samsung");
    EXPECT_EQ(log.header.model, "SM-A520F");
    EXPECT_EQ(log.header.android_api, "26");
    EXPECT_EQ(log.header.android_release, "8.0.0");

    ASSERT_EQ(log.magn.size(), 1u);
    EXPECT_DOUBLE_EQ(log.magn[0].app_s, 0.0527);
    EXPECT_DOUBLE_EQ(log.magn[0].sensor_s, 65093.5402);
    EXPECT_DOUBLE_EQ(log.magn[0].v.y, -34.14);
    EXPECT_EQ(log.magn[0].accuracy, 0);
    ASSERT_EQ(log.gyro.size(), 1u);
    EXPECT_DOUBLE_EQ(log.gyro[0].v.z, 0.09835);
    ASSERT_EQ(log.acce.size(), 1u);
    EXPECT_DOUBLE_EQ(log.acce[0].v.x, -1.01514);
    EXPECT_EQ(log.acce[0].accuracy, 3);
    ASSERT_EQ(log.ahrs.size(), 1u);
    EXPECT_DOUBLE_EQ(log.ahrs[0].pitch_deg, 49.975651);
    EXPECT_DOUBLE_EQ(log.ahrs[0].roll_deg, 11.576796);
    EXPECT_DOUBLE_EQ(log.ahrs[0].yaw_deg, -16.530445);
    EXPECT_DOUBLE_EQ(log.ahrs[0].q2, 0.42904782);
    EXPECT_DOUBLE_EQ(log.ahrs[0].q4, -0.08747417);
    EXPECT_EQ(log.ahrs[0].accuracy, 2);
    ASSERT_EQ(log.soun.size(), 1u);
    EXPECT_DOUBLE_EQ(log.soun[0].rms, 3093.40);
    EXPECT_DOUBLE_EQ(log.soun[0].pressure_pa, 0.09441);
    EXPECT_DOUBLE_EQ(log.soun[0].spl_db, 73.48);
    ASSERT_EQ(log.pres.size(), 1u);
    EXPECT_DOUBLE_EQ(log.pres[0].value, 976.2273);
    EXPECT_DOUBLE_EQ(log.pres[0].sensor_s, 65093.6620);
    ASSERT_EQ(log.ligh.size(), 1u);
    EXPECT_DOUBLE_EQ(log.ligh[0].value, 349.0);
    EXPECT_EQ(log.ligh[0].accuracy, 1);
    ASSERT_EQ(log.prox.size(), 1u);
    EXPECT_DOUBLE_EQ(log.prox[0].value, 8.0);
    ASSERT_EQ(log.humi.size(), 1u);
    EXPECT_DOUBLE_EQ(log.humi[0].value, 41.5);
    ASSERT_EQ(log.temp.size(), 1u);
    EXPECT_DOUBLE_EQ(log.temp[0].value, 23.25);

    ASSERT_EQ(log.wifi.size(), 1u);  // two lines, one AppTimestamp: one scan
    const auto& scan = log.wifi[0];
    EXPECT_DOUBLE_EQ(scan.app_s, 0.651);
    ASSERT_EQ(scan.readings.size(), 2u);
    EXPECT_EQ(scan.readings[0].ssid, "SSID2023_0001");
    EXPECT_EQ(scan.readings[0].bssid.str(), "20:23:00:00:00:01");
    EXPECT_EQ(scan.readings[0].frequency_mhz, 2437);
    EXPECT_DOUBLE_EQ(scan.readings[0].rss_dbm, -60.0);
    EXPECT_DOUBLE_EQ(scan.readings[1].sensor_s, 65094.1801);
    EXPECT_EQ(scan.readings[1].bssid.str(), "20:23:00:00:00:ab");  // normalised like every Locus bssid
    EXPECT_EQ(scan.readings[1].frequency_mhz, 5500);
    EXPECT_EQ(scan.readings[1].line, 21);

    ASSERT_EQ(log.gnss.size(), 1u);
    const auto& g = log.gnss[0];
    EXPECT_DOUBLE_EQ(g.sensor_s, 1686729678.0);
    EXPECT_DOUBLE_EQ(g.lat_deg, 49.461269);
    EXPECT_DOUBLE_EQ(g.lon_deg, 11.111049);
    EXPECT_DOUBLE_EQ(g.altitude_m, 346.0);
    EXPECT_DOUBLE_EQ(g.bearing_deg, 79.5);
    EXPECT_DOUBLE_EQ(g.accuracy_m, 9.0);
    EXPECT_DOUBLE_EQ(g.speed_mps, 0.1);
    EXPECT_EQ(g.sats_in_view, 22);
    EXPECT_EQ(g.sats_in_use, 19);

    ASSERT_EQ(log.ble4.size(), 1u);
    const auto& b = log.ble4[0];
    EXPECT_DOUBLE_EQ(b.app_s, 2.8313);
    EXPECT_EQ(b.mac.str(), "be:ac:20:23:00:01");
    EXPECT_DOUBLE_EQ(b.rssi_dbm, -90.0);
    EXPECT_EQ(b.power, -59);
    EXPECT_EQ(b.major, 1);
    EXPECT_EQ(b.minor, 6);
    EXPECT_EQ(b.uuid, "11111111-1111-BEAC-2023-111111111111");

    ASSERT_EQ(log.blue.size(), 1u);
    EXPECT_EQ(log.blue[0].name, "my phone");
    EXPECT_EQ(log.blue[0].mac.str(), "aa:bb:cc:dd:ee:0f");
    EXPECT_DOUBLE_EQ(log.blue[0].rss_dbm, -71.0);
    ASSERT_EQ(log.rfid.size(), 1u);
    EXPECT_EQ(log.rfid[0].reader, 2);
    EXPECT_EQ(log.rfid[0].tag, 1234567);
    EXPECT_DOUBLE_EQ(log.rfid[0].rss_a_dbm, -60.5);
    EXPECT_DOUBLE_EQ(log.rfid[0].rss_b_dbm, -70.0);

    ASSERT_EQ(log.imux.size(), 1u);
    const auto& x = log.imux[0];
    EXPECT_DOUBLE_EQ(x.sensor_s, 100.5);
    EXPECT_EQ(x.counter, 17);
    EXPECT_DOUBLE_EQ(x.acc.z, 9.8);
    EXPECT_DOUBLE_EQ(x.gyro.y, 0.02);
    EXPECT_DOUBLE_EQ(x.mag.x, 20.0);
    EXPECT_DOUBLE_EQ(x.roll_deg, 1.0);
    EXPECT_DOUBLE_EQ(x.yaw_deg, 3.0);
    EXPECT_DOUBLE_EQ(x.quat[0], 0.9);
    EXPECT_DOUBLE_EQ(x.quat[3], 0.3);
    EXPECT_DOUBLE_EQ(x.pressure_mbar, 1013.5);
    EXPECT_DOUBLE_EQ(x.temperature_c, 24.5);
    ASSERT_EQ(log.imul.size(), 1u);
    EXPECT_EQ(log.imul[0].counter, 18);
    EXPECT_DOUBLE_EQ(log.imul[0].temperature_c, 24.4);
    ASSERT_EQ(log.imui.size(), 1u);
    EXPECT_EQ(log.imui[0].packet, 5);
    EXPECT_EQ(log.imui[0].step, 3);
    EXPECT_DOUBLE_EQ(log.imui[0].dy_m, 0.25);
    EXPECT_DOUBLE_EQ(log.imui[0].dtheta_deg, 12.5);
    EXPECT_DOUBLE_EQ(log.imui[0].covariance[0], 1.0);
    EXPECT_DOUBLE_EQ(log.imui[0].covariance[9], 10.0);

    ASSERT_EQ(log.posi.size(), 1u);
    const auto& p = log.posi[0];
    EXPECT_DOUBLE_EQ(p.app_s, 61.4235);
    EXPECT_EQ(p.counter, 1);
    EXPECT_DOUBLE_EQ(p.lat_deg, 49.461316433032);
    EXPECT_DOUBLE_EQ(p.lon_deg, 11.110964442580);
    EXPECT_EQ(p.floor, -2);
    EXPECT_EQ(p.building, 100);
    EXPECT_EQ(p.line, 29);

    EXPECT_TRUE(log.skipped.empty());
    EXPECT_FALSE(log.truncated_last_line);
    EXPECT_EQ(log.lines, 29);
}

TEST(IpinLog, CrlfReadsAsLf) {
    const auto lf = ipin::parse_log(kAllTags, "a.txt");
    const auto cr = ipin::parse_log(crlf(kAllTags), "a.txt");
    EXPECT_EQ(cr.header.model, "SM-A520F");  // no '\r' kept in header values
    EXPECT_EQ(cr.lines, lf.lines);
    ASSERT_EQ(cr.posi.size(), 1u);
    EXPECT_EQ(cr.posi[0].building, 100);
    ASSERT_EQ(cr.wifi.size(), 1u);
    EXPECT_DOUBLE_EQ(cr.wifi[0].readings[1].rss_dbm, -87.0);
    ASSERT_EQ(cr.ble4.size(), 1u);
    EXPECT_EQ(cr.ble4[0].uuid, lf.ble4[0].uuid);
    EXPECT_EQ(cr.acce.size(), 1u);
    EXPECT_EQ(cr.imui.size(), 1u);
}

TEST(IpinLog, ReadsFromAStream) {
    std::istringstream in(kAllTags);
    const auto log = ipin::parse_log(in, "stream.txt");
    EXPECT_EQ(log.posi.size(), 1u);
    EXPECT_EQ(log.header.android_release, "8.0.0");
}

TEST(IpinLog, UnknownTagsAreCountedPerTagAndSkipped) {
    const auto log = ipin::parse_log(
        "ACCE;1;2;0;0;9.8;3\nGSM0;1.5;whatever\nXYZ1;2\nGSM0;3;x;y\nBLE4;4;Eddystone;AA:BB:CC:DD:EE:FF;-70;abc\nACCE;5;6;0;0;9.8;3\n",
        "u.txt");
    EXPECT_EQ(log.acce.size(), 2u);
    const std::map<std::string, long> expected{{"GSM0", 2}, {"XYZ1", 1}, {"BLE4 Eddystone", 1}};
    EXPECT_EQ(log.skipped, expected);
    EXPECT_TRUE(log.ble4.empty());
}

TEST(IpinLog, MalformedLinesNameFileAndLine) {
    const std::string ok = "% header\nACCE;1;2;0;0;9.8;3\n";
    struct Case {
        std::string line, message;
    };
    const std::vector<Case> cases{
        {"ACCE;2;3;0;0;9.8\n", "expected 6 fields after the tag"},
        {"ACCE;2;3;0;0;9.8;3;4\n", "expected 6 fields after the tag"},
        {"ACCE;2;3;0;zero;9.8;3\n", "y is not a number: 'zero'"},
        {"ACCE;2;3;0;nan;9.8;3\n", "y is not finite"},
        {"GYRO;2;3;inf;0;0;3\n", "x is not finite"},
        {"PRES;2;3;-infinity;3\n", "value is not finite"},
        {"PRES;2;3;976.1;3.5\n", "accuracy is not an integer"},
        {"PRES;2;3;976.1;\n", "expected 4 fields after the tag"},
        {"POSI;2;1;49.4;11.1;zero;100\n", "floor is not an integer"},
        {"POSI;2;1;149.4;11.1;0;100\n", "latitude or longitude out of range"},
        {"WIFI;2;3;ssid;20:23:00:00:00:01;2437\n", "expected 6 fields after the tag"},
        {"WIFI;2;3;ssid; ;2437;-60\n", "BSSID is empty"},
        {"WIFI;2;3;ssid;20:23:00:00:00:01;2437;-6O\n", "RSS is not a number"},
        {"BLE4;2;AltBeacon;BE:AC:20:23:00:01;-90;0;1;1;uuid\n", "neither iBeacon nor Eddystone"},
        {"GNSS;2;3;49.4;11.1;346;0;9;0.1;22\n", "expected 10 fields after the tag"},
        {"acce;2;3;0;0;9.8;3\n", "not 4 capitals or digits"},
        {"just some words\n", "not a data line"},
        {"ACCE\n", "without fields"},
        {"ACCE;0.5;3;0;0;9.8;3\n", "AppTimestamp goes back in time"},
        {"ACCE;;3;0;0;9.8;3\n", "AppTimestamp is not a number"},
        {"ACCE;2;1e17;0;0;9.8;3\n", "SensorTimestamp is outside ±1e10 s"},
        {"GNSS;1e300;3;49.4;11.1;346;0;9;0.1;22;19\n", "AppTimestamp is outside ±1e10 s"},
    };
    for (const auto& c : cases) {
        const auto f = failure_of(ok + c.line, "dir/T01.txt");
        EXPECT_EQ(f.file, "dir/T01.txt") << c.line;
        EXPECT_EQ(f.line, 3) << c.line;
        EXPECT_EQ(f.what.rfind("dir/T01.txt:3: ", 0), 0u) << c.line << " → " << f.what;
        EXPECT_NE(f.what.find(c.message), std::string::npos) << c.line << " → " << f.what;
    }
    // A malformed line in the middle is an error even when later lines are fine.
    const auto mid = failure_of("ACCE;1;2;0;0;9.8;3\r\nACCE;1;2;0;0\r\nACCE;3;4;0;0;9.8;3\r\n");
    EXPECT_EQ(mid.line, 2);
    EXPECT_NE(mid.what.find("expected 6 fields"), std::string::npos) << mid.what;
}

TEST(IpinLog, EmptyAndCommentOnlyFilesGiveAnEmptyLog) {
    const auto empty = ipin::parse_log("", "empty.txt");
    EXPECT_EQ(empty.lines, 0);
    EXPECT_TRUE(empty.acce.empty());
    EXPECT_TRUE(empty.wifi.empty());
    EXPECT_TRUE(empty.skipped.empty());
    EXPECT_FALSE(empty.truncated_last_line);
    const auto header = ipin::parse_log("% Model: \tSM-G930F\n\n\r\n", "h.txt");
    EXPECT_EQ(header.header.model, "SM-G930F");
    EXPECT_EQ(header.lines, 3);
    EXPECT_TRUE(header.posi.empty());
}

TEST(IpinLog, AnUnterminatedLastLineIsDroppedOnlyWhenItDoesNotParse) {
    const std::string body = "ACCE;1;2;0;0;9.8;3\nPRES;1.1;2.1;976.2;3\n";
    // Cut mid-line (the app was stopped, a copy was cut short): dropped and flagged.
    const auto cut = ipin::parse_log(body + "ACCE;1.2;2.2;0.1;0.", "cut.txt");
    EXPECT_TRUE(cut.truncated_last_line);
    EXPECT_EQ(cut.acce.size(), 1u);
    EXPECT_EQ(cut.pres.size(), 1u);
    EXPECT_EQ(cut.lines, 3);
    const auto cut_tag = ipin::parse_log(body + "AC", "cut.txt");
    EXPECT_TRUE(cut_tag.truncated_last_line);
    // A whole line without its newline is kept.
    const auto whole = ipin::parse_log(body + "ACCE;1.2;2.2;0.1;0.2;9.7;3", "whole.txt");
    EXPECT_FALSE(whole.truncated_last_line);
    ASSERT_EQ(whole.acce.size(), 2u);
    EXPECT_DOUBLE_EQ(whole.acce[1].v.z, 9.7);
    // The same cut line followed by a newline is an error: only the end of a file is forgiven.
    EXPECT_EQ(failure_of(body + "ACCE;1.2;2.2;0.1;0.\n").line, 3);
    // A cut WIFI line does not leave a reading in the scan.
    const auto wifi = ipin::parse_log("WIFI;1;2;s;20:23:00:00:00:01;2437;-60\nWIFI;1;2;s;20:23:00:00:00:02;24", "w.txt");
    EXPECT_TRUE(wifi.truncated_last_line);
    ASSERT_EQ(wifi.wifi.size(), 1u);
    EXPECT_EQ(wifi.wifi[0].readings.size(), 1u);
}

TEST(IpinLog, SensorTimestampsAreKeptAsGivenEvenGoingBack) {
    // WIFI's sensor time is when each AP was last seen and the two GNSS providers' fix times
    // interleave: both go back in real files, and are not the shared clock.
    const auto log = ipin::parse_log(
        "GNSS;16.9696;1686729694.0000;49.461277;11.111017;346.000;106.300;10.0;0.3;23;21\n"
        "GNSS;17.2262;1686729675.4430;49.461266;11.110846;366.000;0.000;12.0;0.0;23;21\n"
        "WIFI;18;500.2;a;20:23:00:00:00:01;2437;-60\n"
        "WIFI;18;499.9;b;20:23:00:00:00:02;2412;-70\n",
        "t.txt");
    ASSERT_EQ(log.gnss.size(), 2u);
    EXPECT_DOUBLE_EQ(log.gnss[1].sensor_s, 1686729675.443);
    ASSERT_EQ(log.wifi.size(), 1u);
    EXPECT_DOUBLE_EQ(log.wifi[0].readings[1].sensor_s, 499.9);
    // Equal App timestamps are fine.
    EXPECT_NO_THROW(ipin::parse_log("ACCE;1;2;0;0;9.8;3\nGYRO;1;2;0;0;0;3\n", "eq.txt"));
}

TEST(IpinLog, WifiLinesGroupIntoScans) {
    const auto log = ipin::parse_log(
        "WIFI;10.0;1;n;20:23:00:00:00:01;2437;-60\n"
        "ACCE;10.1;2;0;0;9.8;3\n"
        "WIFI;10.4;1;n;20-23-00-00-00-02;5200;-70\n"  // within 0.5 s of the scan's first line
        "WIFI;10.45;1;n;20:23:00:00:00:01;2437;-61\n"  // the same AP again: a new scan
        "WIFI;11.0;1;n;20:23:00:00:00:03;2412;-80\n"   // 0.55 s after that scan's first line
        "WIFI;11.0;1;my;net;20:23:00:00:00:04;2412;-81;\n",  // ';' in the SSID, a trailing ';'
        "w.txt");
    ASSERT_EQ(log.wifi.size(), 3u);
    EXPECT_DOUBLE_EQ(log.wifi[0].app_s, 10.0);
    ASSERT_EQ(log.wifi[0].readings.size(), 2u);
    EXPECT_EQ(log.wifi[0].readings[1].bssid.str(), "20:23:00:00:00:02");
    EXPECT_DOUBLE_EQ(log.wifi[1].app_s, 10.45);
    EXPECT_EQ(log.wifi[1].readings.size(), 1u);
    EXPECT_DOUBLE_EQ(log.wifi[2].app_s, 11.0);
    ASSERT_EQ(log.wifi[2].readings.size(), 2u);
    EXPECT_EQ(log.wifi[2].readings[1].ssid, "my;net");
    EXPECT_DOUBLE_EQ(log.wifi[2].readings[1].rss_dbm, -81.0);
}

TEST(IpinLog, ConvertsToLocusTypes) {
    const auto log = ipin::parse_log(
        "WIFI;1;1;n;20:23:00:00:00:01;2437;-60\n"
        "WIFI;1;1;n;20:23:00:00:00:02;2437;5\n"  // not a valid RSS for the matchers
        "PRES;1.5;100.2;976.25;3\n"
        "ACCE;2.00;100.00;0;0;9.8;3\n"
        "GYRO;2.05;100.01;0.1;0;0;3\n"
        "ACCE;2.08;100.02;0;1;9.8;3\n"  // received 0.06 s later than the first: late delivery
        "MAGN;2.10;100.03;20;0;-40;0\n",
        "c.txt");
    ASSERT_EQ(log.wifi.size(), 1u);
    const auto scan = ipin::to_scan(log.wifi[0]);
    ASSERT_EQ(scan.size(), 1u);
    EXPECT_EQ(scan[0].type, "wifi");
    EXPECT_EQ(scan[0].bssid.str(), "20:23:00:00:00:01");
    EXPECT_DOUBLE_EQ(scan[0].rss, -60.0);

    const auto p = ipin::pressure_series(log);
    ASSERT_EQ(p.size(), 1u);
    EXPECT_DOUBLE_EQ(p[0].t_s, 1.5);
    EXPECT_DOUBLE_EQ(p[0].hpa, 976.25);

    // Sensor clock, moved by ACCE's smallest App − Sensor (2.00 − 100.00 = −98).
    const auto acc = ipin::accel_samples(log);
    ASSERT_EQ(acc.size(), 2u);
    EXPECT_NEAR(acc[0].t_s, 2.00, 1e-9);
    EXPECT_NEAR(acc[1].t_s, 2.02, 1e-9);
    EXPECT_DOUBLE_EQ(acc[1].ay, 1.0);
    const auto acc_app = ipin::accel_samples(log, ipin::Clock::app);
    EXPECT_DOUBLE_EQ(acc_app[1].t_s, 2.08);

    const auto imu = ipin::imu_samples(log, ipin::Clock::app);
    ASSERT_EQ(imu.size(), 4u);
    EXPECT_EQ(imu[0].sensor, locus::datasets::ImuSensor::acc);
    EXPECT_EQ(imu[1].sensor, locus::datasets::ImuSensor::gyro);
    EXPECT_DOUBLE_EQ(imu[1].v.x, 0.1);
    EXPECT_EQ(imu[2].sensor, locus::datasets::ImuSensor::acc);
    EXPECT_EQ(imu[3].sensor, locus::datasets::ImuSensor::mag);
    EXPECT_DOUBLE_EQ(imu[3].v.z, -40.0);
    for (std::size_t i = 1; i < imu.size(); ++i) EXPECT_LE(imu[i - 1].t_s, imu[i].t_s);
}

TEST(IpinLog, TellsItsFormatFromTheFirstLine) {
    EXPECT_TRUE(ipin::looks_like_log("% LogFile created by the 'GetSensorData' App\n"));
    EXPECT_TRUE(ipin::looks_like_log("\r\nACCE;0.05;65093.5;-1.0;8.2;6.2;3\n"));
    EXPECT_FALSE(ipin::looks_like_log("t,sensor,x,y,z\n0.0,acc,0,0,9.8\n"));
    EXPECT_FALSE(ipin::looks_like_log("1000000,3,0.1,0.2,9.8\n"));
    EXPECT_FALSE(ipin::looks_like_log(""));
}

TEST(IpinLog, MissingFileIsALogError) {
    try {
        ipin::read_log("/nonexistent/ipin.txt");
        FAIL() << "no error";
    } catch (const ipin::LogError& e) {
        EXPECT_EQ(e.file(), "/nonexistent/ipin.txt");
        EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
    }
}

// --- The IPIN 2023 Track 3 walks (../shared/data/ipin2023) ---

const std::string kTrials = std::string(LOCUS_DATA_DIR) + "/ipin2023/trials";

// The README's local frame: equirectangular around lat 49.46115, lon 11.11115.
std::pair<double, double> local_m(double lat, double lon) {
    constexpr double kDeg = 3.14159265358979323846 / 180.0;
    return {(lon - 11.11115) * kDeg * 6390503.0 * std::cos(49.46115 * kDeg), (lat - 49.46115) * kDeg * 6372360.0};
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

template <class Sample>
double median_interval(const std::vector<Sample>& v) {
    std::vector<double> d;
    for (std::size_t i = 1; i < v.size(); ++i) d.push_back(v[i].sensor_s - v[i - 1].sensor_s);
    return median(d);
}

// The README's phone table: T01–T05, T22–T25, T27: A5 A5 S7; T21, T26: S7 S7 A5; T52: S7.
std::string expected_model(int route, int rep) {
    const bool s7_first = route == 21 || route == 26 || route == 52;
    const bool s7 = s7_first ? rep != 3 : rep == 3;
    return s7 ? "SM-G930F" : "SM-A520F";
}

TEST(IpinLogData, ReadsTheIpin2023WalksAsTheReadmeDescribes) {
    if (!std::filesystem::is_directory(kTrials)) GTEST_SKIP() << "IPIN 2023 walks not found under " << kTrials;
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(kTrials))
        if (e.path().extension() == ".txt") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    ASSERT_EQ(files.size(), 37u);

    std::set<std::pair<double, double>> landmarks;
    std::set<std::string> bssids;
    std::vector<double> all_sizes;
    const auto t0 = std::chrono::steady_clock::now();
    for (const auto& path : files) {
        const std::string name = path.filename().string();
        SCOPED_TRACE(name);
        const int route = std::stoi(name.substr(name.find("Trial") + 5, 2));
        const int rep = std::stoi(name.substr(name.find("repetition") + 10, 2));
        const auto log = ipin::read_log(path.string());
        EXPECT_TRUE(log.skipped.empty());  // only the README's tags
        EXPECT_FALSE(log.truncated_last_line);
        EXPECT_EQ(log.header.model, expected_model(route, rep));
        EXPECT_EQ(log.header.manufacturer, "samsung");
        EXPECT_EQ(log.header.android_release, "8.0.0");
        EXPECT_TRUE(log.header.created.find("Jun 14") != std::string::npos ||
                    log.header.created.find("Jun 15") != std::string::npos)
            << log.header.created;
        const bool s7 = log.header.model == "SM-G930F";

        // Ground truth: 10–26 POSI, the first 60–74 s in, the walk 80–190 s, building 100.
        ASSERT_GE(log.posi.size(), 10u);
        EXPECT_LE(log.posi.size(), 26u);
        EXPECT_GE(log.posi.front().app_s, 60.0);
        EXPECT_LE(log.posi.front().app_s, 75.0);
        const double walk_s = log.posi.back().app_s - log.posi.front().app_s;
        EXPECT_GE(walk_s, 80.0);
        EXPECT_LE(walk_s, 190.0);
        std::vector<int> floors;
        for (const auto& p : log.posi) {
            EXPECT_EQ(p.building, 100);
            floors.push_back(p.floor);
            const auto [x, y] = local_m(p.lat_deg, p.lon_deg);
            EXPECT_LT(std::abs(x), 100.0);  // the landmarks span ~100 m × 50 m
            EXPECT_LT(std::abs(y), 60.0);
            landmarks.insert({p.lat_deg, p.lon_deg});
        }
        if (route == 52) {
            EXPECT_EQ(floors, (std::vector<int>{0, -2, -2, -2, -2, 0, 0, -2, -2, -2, -2, 0}));
        } else {
            for (int f : floors) EXPECT_EQ(f, route <= 5 ? 0 : -2);
        }

        // Sensor rates from the sensor timestamps (README's table, ±20 %).
        EXPECT_NEAR(median_interval(log.acce), 1.0 / 50, 0.2 / 50);
        EXPECT_NEAR(median_interval(log.magn), 1.0 / 50, 0.2 / 50);
        EXPECT_NEAR(median_interval(log.gyro), s7 ? 1.0 / 50 : 1.0 / 100, s7 ? 0.2 / 50 : 0.2 / 100);
        if (s7) {
            EXPECT_NEAR(median_interval(log.pres), 0.1, 0.02);
        } else {
            EXPECT_NEAR(median_interval(log.pres), 1.0 / 5.85, 0.03);
        }
        // Delivery delay, App − Sensor less a constant: at worst 0.35 s.
        double lo = 1e300, hi = -1e300;
        for (const auto& s : log.acce) lo = std::min(lo, s.app_s - s.sensor_s), hi = std::max(hi, s.app_s - s.sensor_s);
        EXPECT_LE(hi - lo, 0.4);

        // Pressure in mbar; only changes carry the floor. T52: floor -2 ≈ 0.66 mbar above 0.
        for (const auto& p : log.pres) {
            EXPECT_GT(p.value, 950.0);
            EXPECT_LT(p.value, 1050.0);
        }
        if (route == 52) {
            std::vector<double> on0, on2;
            for (const auto& q : log.posi) {
                std::vector<double> near;
                for (const auto& p : log.pres)
                    if (std::abs(p.app_s - q.app_s) < 1.0) near.push_back(p.value);
                (q.floor == 0 ? on0 : on2).push_back(median(near));
            }
            EXPECT_NEAR(median(on2) - median(on0), 0.66, 0.2);
        }

        // WiFi: scans every 4.0 s (A5) or 2.0 s (S7), ~15–18 APs, anonymised ids, 2.4/5 GHz.
        ASSERT_GE(log.wifi.size(), 10u);
        std::vector<double> gaps, sizes;
        for (std::size_t i = 0; i < log.wifi.size(); ++i) {
            if (i > 0) gaps.push_back(log.wifi[i].app_s - log.wifi[i - 1].app_s);
            sizes.push_back(static_cast<double>(log.wifi[i].readings.size()));
            for (const auto& r : log.wifi[i].readings) {
                // The README writes them 20:23:00:00:00:xx; the files' numbers run over the
                // last two groups (20:23:00:00:01:88).
                EXPECT_EQ(r.bssid.str().rfind("20:23:00:00:0", 0), 0u) << r.bssid.str();
                EXPECT_EQ(r.ssid.rfind("SSID2023_", 0), 0u) << r.ssid;
                EXPECT_TRUE((r.frequency_mhz >= 2400 && r.frequency_mhz < 2500) ||
                            (r.frequency_mhz >= 5150 && r.frequency_mhz < 5900))
                    << r.frequency_mhz;
                EXPECT_TRUE(locus::valid_rss(r.rss_dbm)) << r.rss_dbm;
                bssids.insert(r.bssid.str());
            }
        }
        EXPECT_NEAR(median(gaps), s7 ? 2.0 : 4.0, 0.5);
        // ~15–18 APs a scan over all walks; the stairs walk T52 hears fewer.
        EXPECT_GE(median(sizes), 5.0);
        EXPECT_LE(median(sizes), 25.0);
        all_sizes.insert(all_sizes.end(), sizes.begin(), sizes.end());

        // GNSS: the sensor timestamp is the fix's UTC time, 14–15 June 2023.
        for (const auto& g : log.gnss) {
            EXPECT_GE(g.sensor_s, 1686700800.0);  // 2023-06-14T00:00Z
            EXPECT_LT(g.sensor_s, 1686873600.0);  // 2023-06-16T00:00Z
        }
        // SOUN at 2 Hz (App clock: the line has no sensor timestamp).
        std::vector<double> sound_gaps;
        for (std::size_t i = 1; i < log.soun.size(); ++i) sound_gaps.push_back(log.soun[i].app_s - log.soun[i - 1].app_s);
        EXPECT_NEAR(median(sound_gaps), 0.5, 0.1);

        // BLE4: only the 6 competition beacons, MAC BE:AC:20:23:00:0n, major 1, minor n.
        for (const auto& b : log.ble4) {
            EXPECT_EQ(b.major, 1);
            ASSERT_GE(b.minor, 1);
            ASSERT_LE(b.minor, 6);
            EXPECT_EQ(b.mac.str(), "be:ac:20:23:00:0" + std::to_string(b.minor));
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "[ipin2023] 37 logfiles read and checked in " << seconds << " s\n";
    EXPECT_EQ(landmarks.size(), 74u);
    EXPECT_EQ(bssids.size(), 219u);
    EXPECT_GE(median(all_sizes), 14.0);
    EXPECT_LE(median(all_sizes), 19.0);
}

}  // namespace
}  // namespace ipin_log_test
