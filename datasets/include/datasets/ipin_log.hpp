#pragma once
// locus_datasets (datasets/): the data set and file readers, a library apart from the CLI so that
// tests, benchmarks and fuzz targets read a file exactly as the commands do.
//
// Reader of the logfiles of LOPSI's GetSensorData Android app, the format of the IPIN
// competitions' smartphone tracks (e.g. IPIN 2023 Track 3, ../shared/data/ipin2023/README.md;
// docs/ipin.md). A header of '%' lines, then one sample per ';'-separated line that starts
// with a 4-letter tag. Every tag the app's format header documents is read into its own typed
// vector, values and both timestamps exactly as written (seconds; AppTimestamp is the clock
// shared by all sensors, SensorTimestamp each sensor's own). Cost: one pass over the text,
// O(lines); the whole text is held in memory while parsing (a 37-walk competition folder is
// about 100 MB).
//
// Error policy (docs/ipin.md): a malformed line (wrong field count, a non-numeric or
// non-finite number, a timestamp of the shared App clock going back) throws LogError naming the
// file and line. Skipped and counted instead: '%' lines (the known header keys are kept),
// blank lines, lines with an unknown 4-character tag (per tag), BLE4 Eddystone frames, and an
// unterminated last line that does not parse (a file cut mid-line).
#include <array>
#include <istream>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "datasets/pdr_logs.hpp"
#include "locus/motion/pdr/vec3.hpp"
#include "locus/radio_map.hpp"

namespace locus::datasets::ipin {

// What every reader error of this format is; what() reads "FILE:LINE: message".
class LogError : public std::runtime_error {
public:
    LogError(const std::string& file, long line, const std::string& message);
    const std::string& file() const { return file_; }
    long line() const { return line_; }

private:
    std::string file_;
    long line_;
};

// The '%' header's phone description, each field as written (empty when the header lacks it).
struct Header {
    std::string created;          // "% Date of creation: Wed Jun 14 10:00:58 GMT+02:00 2023"
    std::string app_version;      // "% Version 2.21 July 2021" → "2.21 July 2021"
    std::string manufacturer;     // "samsung"
    std::string model;            // "SM-A520F"
    std::string android_api;      // "26"
    std::string android_release;  // "8.0.0"
};

// ACCE (m/s², gravity included), GYRO (rad/s), MAGN (µT): phone axes.
struct Triad {
    double app_s = 0.0, sensor_s = 0.0;
    pdr::Vec3 v;
    int accuracy = 0;
};

// AHRS: the rotation-vector orientation, degrees, and the quaternion's vector part q2..q4.
struct Ahrs {
    double app_s = 0.0, sensor_s = 0.0;
    double pitch_deg = 0.0, roll_deg = 0.0, yaw_deg = 0.0;
    double q2 = 0.0, q3 = 0.0, q4 = 0.0;
    int accuracy = 0;
};

// PRES (mbar = hPa), LIGH (lux), PROX (the sensor's unit, often cm), HUMI (%), TEMP (°C).
struct Scalar {
    double app_s = 0.0, sensor_s = 0.0;
    double value = 0.0;
    int accuracy = 0;
};

// SOUN: no sensor timestamp.
struct Sound {
    double app_s = 0.0;
    double rms = 0.0;
    double pressure_pa = 0.0;
    double spl_db = 0.0;
};

// GNSS: sensor_s is the fix's UTC time (Unix epoch seconds).
struct Gnss {
    double app_s = 0.0, sensor_s = 0.0;
    double lat_deg = 0.0, lon_deg = 0.0, altitude_m = 0.0, bearing_deg = 0.0;
    double accuracy_m = 0.0, speed_mps = 0.0;
    int sats_in_view = 0, sats_in_use = 0;
};

// One WIFI line. sensor_s is when the AP was last seen; it may precede earlier lines'.
struct Wifi {
    double app_s = 0.0, sensor_s = 0.0;
    std::string ssid;  // as written (may hold spaces or ';')
    Bssid bssid;       // normalised (locus/radio_map.hpp)
    int frequency_mhz = 0;
    double rss_dbm = 0.0;
    long line = 0;
};

// A scan: a run of WIFI lines within 0.5 s of its first line's AppTimestamp, no BSSID twice.
struct WifiScan {
    double app_s = 0.0;  // the first line's
    std::vector<Wifi> readings;
};

// BLE4 iBeacon advertisement.
struct Ble4 {
    double app_s = 0.0;
    Bssid mac;  // normalised
    double rssi_dbm = 0.0;
    int power = 0;  // the advertised calibrated power, as written
    int major = 0, minor = 0;
    std::string uuid;
};

// BLUE: classic Bluetooth.
struct Bluetooth {
    double app_s = 0.0;
    std::string name;
    Bssid mac;
    double rss_dbm = 0.0;
};

// POSI: a ground-truth landmark the walker stepped on at app_s.
struct Posi {
    double app_s = 0.0;
    long long counter = 0;
    double lat_deg = 0.0, lon_deg = 0.0;
    int floor = 0, building = 0;
    long line = 0;
};

// RFID: an RFCode reader's reading of a tag on its two antennas.
struct Rfid {
    double app_s = 0.0;
    long long reader = 0, tag = 0;
    double rss_a_dbm = 0.0, rss_b_dbm = 0.0;
};

// IMUX (XSens) and IMUL (LPMS-B): an external IMU's full sample.
struct ExternalImu {
    double app_s = 0.0, sensor_s = 0.0;
    long long counter = 0;
    pdr::Vec3 acc, gyro, mag;  // m/s², rad/s, µT
    double roll_deg = 0.0, pitch_deg = 0.0, yaw_deg = 0.0;
    std::array<double, 4> quat{};  // Quat(1..4)
    double pressure_mbar = 0.0, temperature_c = 0.0;
};

// IMUI (MIMU22BT foot-mounted IMU): one step's displacement and its covariance.
struct FootImu {
    double app_s = 0.0;
    long long packet = 0, step = 0;
    double dx_m = 0.0, dy_m = 0.0, dz_m = 0.0, dtheta_deg = 0.0;
    std::array<double, 10> covariance{};  // the upper triangle of the 4×4, as written
};

struct Log {
    std::string file;
    Header header;
    std::vector<Triad> acce, gyro, magn;
    std::vector<Ahrs> ahrs;
    std::vector<Scalar> pres, ligh, prox, humi, temp;
    std::vector<Sound> soun;
    std::vector<Gnss> gnss;
    std::vector<WifiScan> wifi;
    std::vector<Ble4> ble4;
    std::vector<Bluetooth> blue;
    std::vector<Posi> posi;
    std::vector<Rfid> rfid;
    std::vector<ExternalImu> imux, imul;
    std::vector<FootImu> imui;
    // Data lines not read, per tag ("BLE4 Eddystone" for those frames).
    std::map<std::string, long> skipped;
    long lines = 0;  // lines in the text, the last one counted even if unterminated
    // The last line had no newline and did not parse: dropped (a file cut mid-line).
    bool truncated_last_line = false;
};

// Parsers of a logfile's text; `file` names it in errors. CRLF and LF line ends both.
Log parse_log(std::string_view text, const std::string& file);
Log parse_log(std::istream& in, const std::string& file);
// Reads and parses the file at `path` (LogError "cannot open" when it cannot be read).
Log read_log(const std::string& path);

// Whether a text starting with `head` (the file's first bytes) is this format: its first
// non-blank line is a '%' header line or a tag of 4 capitals/digits followed by ';'. For tools
// that take several formats; cost O(first line).
bool looks_like_log(std::string_view head);
// looks_like_log() on the file's first 4 KiB (false when it cannot be read).
bool file_looks_like_log(const std::string& path);

// --- Conversions to what the rest of Locus uses (pure, no I/O) ---

// A scan as the matchers take it: type "wifi", normalised bssid, rss; readings outside
// [kMinRss, kMaxRss] are dropped (locus/radio_map.hpp), the rest kept in file order.
Scan to_scan(const WifiScan& s);

struct PressureSample {
    double t_s = 0.0;  // AppTimestamp
    double hpa = 0.0;
};
std::vector<PressureSample> pressure_series(const Log& log);

// Which clock inertial samples are stamped with. `sensor`: each sensor's SensorTimestamp
// moved onto the App clock by that sensor's smallest App − Sensor difference, so the
// intervals are the true sampling intervals and no sample is dated after it was received.
enum class Clock { app, sensor };

// ACCE as the step detector's input (`locus pdr steps`), sorted by time.
std::vector<AccelSample> accel_samples(const Log& log, Clock clock = Clock::sensor);
// ACCE, GYRO and MAGN merged as `locus pdr track`'s IMU log, sorted by time (stable).
std::vector<ImuSample> imu_samples(const Log& log, Clock clock = Clock::sensor);

}  // namespace locus::datasets::ipin
