#include "datasets/ipin_log.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <unordered_set>

namespace locus::datasets::ipin {

LogError::LogError(const std::string& file, long line, const std::string& message)
    : std::runtime_error(file + ":" + std::to_string(line) + ": " + message), file_(file), line_(line) {}

namespace {

// A scan's lines carry one AppTimestamp in the IPIN 2023 files; the README allows ~0.5 s.
constexpr double kScanWindowS = 0.5;
// Timestamps are seconds since the app started, of phone uptime or of the Unix epoch (GNSS):
// all far below 1e10 s (year 2286). Past it a double's resolution nears what the step
// detector's 100 Hz grid can step over, so a larger value is an error, not a time.
constexpr double kMaxTimestampS = 1e10;

// Thrown inside a line, turned into a LogError with the file and line by the caller.
struct Bad {
    std::string message;
};

std::string shown(std::string_view s) {
    constexpr std::size_t kMax = 40;
    return "'" + std::string(s.substr(0, kMax)) + (s.size() > kMax ? "…" : "") + "'";
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

double number(std::string_view raw, const char* what) {
    const auto s = trim(raw);
    double v = 0.0;
    // from_chars takes no '+'; the app never writes one, but a hand-edited file may.
    const std::string_view body = !s.empty() && s.front() == '+' ? s.substr(1) : s;
    const auto [p, ec] = std::from_chars(body.data(), body.data() + body.size(), v);
    if (body.empty() || ec != std::errc() || p != body.data() + body.size())
        throw Bad{std::string(what) + " is not a number: " + shown(raw)};
    if (!std::isfinite(v)) throw Bad{std::string(what) + " is not finite: " + shown(raw)};
    return v;
}

long long integer(std::string_view raw, const char* what) {
    const auto s = trim(raw);
    long long v = 0;
    const std::string_view body = !s.empty() && s.front() == '+' ? s.substr(1) : s;
    const auto [p, ec] = std::from_chars(body.data(), body.data() + body.size(), v);
    if (body.empty() || ec != std::errc() || p != body.data() + body.size())
        throw Bad{std::string(what) + " is not an integer: " + shown(raw)};
    return v;
}

int small_int(std::string_view raw, const char* what) {
    const long long v = integer(raw, what);
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
        throw Bad{std::string(what) + " is out of range: " + shown(raw)};
    return static_cast<int>(v);
}

bool is_tag(std::string_view s) {
    return s.size() == 4 && std::all_of(s.begin(), s.end(), [](char c) { return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'); });
}

// The ';'-separated fields of a data line. The app's format header ends some formats with a
// ';' (WIFI, SOUN, POSI, …), so one empty last field is dropped.
void split(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    std::size_t b = 0;
    while (true) {
        const auto e = line.find(';', b);
        if (e == std::string_view::npos) {
            out.push_back(line.substr(b));
            break;
        }
        out.push_back(line.substr(b, e - b));
        b = e + 1;
    }
    if (out.size() > 1 && trim(out.back()).empty()) out.pop_back();
}

void expect(const std::vector<std::string_view>& f, std::size_t n, const char* format) {
    if (f.size() != n)
        throw Bad{"expected " + std::to_string(n - 1) + " fields after the tag (" + format + "), got " +
                  std::to_string(f.size() - 1)};
}

// Fields [b, e) joined back with ';': a name that held one.
std::string joined(const std::vector<std::string_view>& f, std::size_t b, std::size_t e) {
    std::string s;
    for (std::size_t i = b; i < e; ++i) {
        if (i > b) s += ';';
        s += f[i];
    }
    return s;
}

Bssid mac(std::string_view raw, const char* what) {
    Bssid b(raw);
    if (b.empty()) throw Bad{std::string(what) + " is empty"};
    return b;
}

// "% Key:  <tab>value" → the value, if the line is that key's.
bool header_value(std::string_view line, std::string_view key, std::string& out) {
    auto rest = trim(line.substr(1));
    if (rest.substr(0, key.size()) != key) return false;
    out = std::string(trim(rest.substr(key.size())));
    return true;
}

void read_header(std::string_view line, Header& h) {
    if (header_value(line, "Date of creation:", h.created) || header_value(line, "Manufacturer:", h.manufacturer) ||
        header_value(line, "Model:", h.model) || header_value(line, "API Android version:", h.android_api) ||
        header_value(line, "Android version Release:", h.android_release))
        return;
    // "% Version 2.21 July 2021": only the first such line, the app's.
    if (h.app_version.empty()) header_value(line, "Version ", h.app_version);
}

double timestamp(std::string_view raw, const char* what) {
    const double t = number(raw, what);
    if (std::abs(t) > kMaxTimestampS) throw Bad{std::string(what) + " is outside ±1e10 s: " + shown(raw)};
    return t;
}

class Parser {
public:
    Parser(Log& log) : log_(log) {}

    void line(std::string_view text) {
        split(text, f_);
        const std::string_view tag = trim(f_[0]);
        if (f_.size() < 2) {
            if (is_tag(tag)) throw Bad{"a data line without fields after its tag"};
            throw Bad{"not a data line (a 4-letter tag and ';'-separated fields) nor a '%' comment: " + shown(text)};
        }
        if (!is_tag(tag)) throw Bad{"the tag " + shown(tag) + " is not 4 capitals or digits"};
        // Dispatch on the tag's 4 bytes.
        if (tag == "ACCE") return triad(log_.acce, "App;Sensor;ax;ay;az;accuracy");
        if (tag == "GYRO") return triad(log_.gyro, "App;Sensor;gx;gy;gz;accuracy");
        if (tag == "MAGN") return triad(log_.magn, "App;Sensor;mx;my;mz;accuracy");
        if (tag == "PRES") return scalar(log_.pres, "App;Sensor;pressure;accuracy");
        if (tag == "LIGH") return scalar(log_.ligh, "App;Sensor;light;accuracy");
        if (tag == "PROX") return scalar(log_.prox, "App;Sensor;proximity;accuracy");
        if (tag == "HUMI") return scalar(log_.humi, "App;Sensor;humidity;accuracy");
        if (tag == "TEMP") return scalar(log_.temp, "App;Sensor;temperature;accuracy");
        if (tag == "AHRS") return ahrs();
        if (tag == "SOUN") return sound();
        if (tag == "GNSS") return gnss();
        if (tag == "WIFI") return wifi();
        if (tag == "BLE4") return ble4();
        if (tag == "BLUE") return blue();
        if (tag == "POSI") return posi();
        if (tag == "RFID") return rfid();
        if (tag == "IMUX") return external_imu(log_.imux);
        if (tag == "IMUL") return external_imu(log_.imul);
        if (tag == "IMUI") return foot_imu();
        ++log_.skipped[std::string(tag)];
    }

    long line_no = 0;

private:
    // The shared App clock: set as the app receives each sample and written in that order.
    double app(std::string_view raw) {
        const double t = timestamp(raw, "AppTimestamp");
        if (t < last_app_)
            throw Bad{"AppTimestamp goes back in time (" + std::string(trim(raw)) + " s after " + std::to_string(last_app_) +
                      " s): the app writes one clock in order"};
        last_app_ = t;
        return t;
    }

    void triad(std::vector<Triad>& out, const char* format) {
        expect(f_, 7, format);
        Triad s;
        s.app_s = app(f_[1]);
        s.sensor_s = timestamp(f_[2], "SensorTimestamp");
        s.v = {number(f_[3], "x"), number(f_[4], "y"), number(f_[5], "z")};
        s.accuracy = small_int(f_[6], "accuracy");
        out.push_back(s);
    }

    void scalar(std::vector<Scalar>& out, const char* format) {
        expect(f_, 5, format);
        Scalar s;
        s.app_s = app(f_[1]);
        s.sensor_s = timestamp(f_[2], "SensorTimestamp");
        s.value = number(f_[3], "value");
        s.accuracy = small_int(f_[4], "accuracy");
        out.push_back(s);
    }

    void ahrs() {
        expect(f_, 10, "App;Sensor;pitch;roll;yaw;q2;q3;q4;accuracy");
        Ahrs s;
        s.app_s = app(f_[1]);
        s.sensor_s = timestamp(f_[2], "SensorTimestamp");
        s.pitch_deg = number(f_[3], "pitch");
        s.roll_deg = number(f_[4], "roll");
        s.yaw_deg = number(f_[5], "yaw");
        s.q2 = number(f_[6], "q2");
        s.q3 = number(f_[7], "q3");
        s.q4 = number(f_[8], "q4");
        s.accuracy = small_int(f_[9], "accuracy");
        log_.ahrs.push_back(s);
    }

    void sound() {
        expect(f_, 5, "App;RMS;pressure;SPL");
        Sound s;
        s.app_s = app(f_[1]);
        s.rms = number(f_[2], "RMS");
        s.pressure_pa = number(f_[3], "pressure");
        s.spl_db = number(f_[4], "SPL");
        log_.soun.push_back(s);
    }

    void gnss() {
        expect(f_, 11, "App;Sensor;lat;lon;altitude;bearing;accuracy;speed;sats in view;sats in use");
        Gnss s;
        s.app_s = app(f_[1]);
        s.sensor_s = timestamp(f_[2], "SensorTimestamp");
        s.lat_deg = number(f_[3], "latitude");
        s.lon_deg = number(f_[4], "longitude");
        if (std::abs(s.lat_deg) > 90.0 || std::abs(s.lon_deg) > 180.0) throw Bad{"latitude or longitude out of range"};
        s.altitude_m = number(f_[5], "altitude");
        s.bearing_deg = number(f_[6], "bearing");
        s.accuracy_m = number(f_[7], "accuracy");
        s.speed_mps = number(f_[8], "speed");
        s.sats_in_view = small_int(f_[9], "satellites in view");
        s.sats_in_use = small_int(f_[10], "satellites in use");
        log_.gnss.push_back(s);
    }

    void wifi() {
        // The SSID may hold ';': it is everything between the sensor timestamp and the BSSID.
        if (f_.size() < 7)
            throw Bad{"expected 6 fields after the tag (App;Sensor;SSID;BSSID;frequency;RSS), got " + std::to_string(f_.size() - 1)};
        const std::size_t n = f_.size();
        Wifi w;
        w.line = line_no;
        w.app_s = app(f_[1]);
        w.sensor_s = timestamp(f_[2], "SensorTimestamp");
        w.ssid = joined(f_, 3, n - 3);
        w.bssid = mac(f_[n - 3], "BSSID");
        w.frequency_mhz = small_int(f_[n - 2], "frequency");
        w.rss_dbm = number(f_[n - 1], "RSS");
        auto& scans = log_.wifi;
        if (scans.empty() || w.app_s - scans.back().app_s > kScanWindowS || !scan_bssids_.insert(w.bssid.str()).second) {
            scans.push_back(WifiScan{w.app_s, {}});
            scan_bssids_.clear();
            scan_bssids_.insert(w.bssid.str());
        }
        scans.back().readings.push_back(std::move(w));
    }

    void ble4() {
        if (f_.size() >= 3 && trim(f_[2]) == "Eddystone") {
            app(f_[1]);
            ++log_.skipped["BLE4 Eddystone"];
            return;
        }
        expect(f_, 9, "App;iBeacon;MAC;RSSI;power;major;minor;UUID");
        if (trim(f_[2]) != "iBeacon") throw Bad{"BLE4 frame type " + shown(f_[2]) + " is neither iBeacon nor Eddystone"};
        Ble4 b;
        b.app_s = app(f_[1]);
        b.mac = mac(f_[3], "MAC");
        b.rssi_dbm = number(f_[4], "RSSI");
        b.power = small_int(f_[5], "power");
        b.major = small_int(f_[6], "major");
        b.minor = small_int(f_[7], "minor");
        b.uuid = std::string(trim(f_[8]));
        log_.ble4.push_back(std::move(b));
    }

    void blue() {
        // 'BLUE;App;Name;MAC;RSS': the name may hold ';'.
        if (f_.size() < 5) throw Bad{"expected 4 fields after the tag (App;name;MAC;RSS), got " + std::to_string(f_.size() - 1)};
        const std::size_t n = f_.size();
        Bluetooth b;
        b.app_s = app(f_[1]);
        b.name = joined(f_, 2, n - 2);
        b.mac = mac(f_[n - 2], "MAC");
        b.rss_dbm = number(f_[n - 1], "RSS");
        log_.blue.push_back(std::move(b));
    }

    void posi() {
        expect(f_, 7, "App;counter;lat;lon;floor;building");
        Posi p;
        p.line = line_no;
        p.app_s = app(f_[1]);
        p.counter = integer(f_[2], "counter");
        p.lat_deg = number(f_[3], "latitude");
        p.lon_deg = number(f_[4], "longitude");
        if (std::abs(p.lat_deg) > 90.0 || std::abs(p.lon_deg) > 180.0) throw Bad{"latitude or longitude out of range"};
        p.floor = small_int(f_[5], "floor");
        p.building = small_int(f_[6], "building");
        log_.posi.push_back(p);
    }

    void rfid() {
        expect(f_, 6, "App;reader;tag;RSS_A;RSS_B");
        Rfid r;
        r.app_s = app(f_[1]);
        r.reader = integer(f_[2], "reader");
        r.tag = integer(f_[3], "tag");
        r.rss_a_dbm = number(f_[4], "RSS_A");
        r.rss_b_dbm = number(f_[5], "RSS_B");
        log_.rfid.push_back(r);
    }

    void external_imu(std::vector<ExternalImu>& out) {
        expect(f_, 22, "App;Sensor;counter;acc xyz;gyro xyz;mag xyz;roll;pitch;yaw;quat 1-4;pressure;temperature");
        ExternalImu s;
        s.app_s = app(f_[1]);
        s.sensor_s = timestamp(f_[2], "SensorTimestamp");
        s.counter = integer(f_[3], "counter");
        s.acc = {number(f_[4], "acc x"), number(f_[5], "acc y"), number(f_[6], "acc z")};
        s.gyro = {number(f_[7], "gyro x"), number(f_[8], "gyro y"), number(f_[9], "gyro z")};
        s.mag = {number(f_[10], "mag x"), number(f_[11], "mag y"), number(f_[12], "mag z")};
        s.roll_deg = number(f_[13], "roll");
        s.pitch_deg = number(f_[14], "pitch");
        s.yaw_deg = number(f_[15], "yaw");
        for (std::size_t i = 0; i < 4; ++i) s.quat[i] = number(f_[16 + i], "quaternion");
        s.pressure_mbar = number(f_[20], "pressure");
        s.temperature_c = number(f_[21], "temperature");
        out.push_back(s);
    }

    void foot_imu() {
        expect(f_, 18, "App;packet;step;dx;dy;dz;dtheta;covariance[10]");
        FootImu s;
        s.app_s = app(f_[1]);
        s.packet = integer(f_[2], "packet count");
        s.step = integer(f_[3], "step counter");
        s.dx_m = number(f_[4], "delta x");
        s.dy_m = number(f_[5], "delta y");
        s.dz_m = number(f_[6], "delta z");
        s.dtheta_deg = number(f_[7], "delta theta");
        for (std::size_t i = 0; i < 10; ++i) s.covariance[i] = number(f_[8 + i], "covariance");
        log_.imui.push_back(s);
    }

    Log& log_;
    std::vector<std::string_view> f_;
    double last_app_ = -std::numeric_limits<double>::infinity();
    std::unordered_set<std::string> scan_bssids_;
};

bool blank(std::string_view line) { return line.find_first_not_of(" \t\r") == std::string_view::npos; }

}  // namespace

Log parse_log(std::string_view text, const std::string& file) {
    Log log;
    log.file = file;
    Parser p(log);
    std::size_t pos = 0;
    long n = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        const bool terminated = end != std::string_view::npos;
        if (!terminated) end = text.size();
        ++n;
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (blank(line)) continue;
        if (line.front() == '%') {
            read_header(line, log.header);
            continue;
        }
        p.line_no = n;
        // Every field of a line is checked before its sample is pushed, so a dropped last
        // line leaves nothing of itself behind.
        try {
            p.line(line);
        } catch (const Bad& e) {
            if (!terminated) {
                log.truncated_last_line = true;
                break;
            }
            throw LogError(file, n, e.message);
        }
    }
    log.lines = n;
    return log;
}

Log parse_log(std::istream& in, const std::string& file) {
    // One bulk copy: a loop of istreambuf_iterator steps costs more than parsing the text, and
    // some 25 times more under the sanitizers.
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw LogError(file, 0, "read error");
    const std::string text = std::move(buffer).str();
    return parse_log(std::string_view(text), file);
}

Log read_log(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw LogError(path, 0, "cannot open");
    return parse_log(in, path);
}

bool looks_like_log(std::string_view head) {
    std::size_t pos = 0;
    while (pos < head.size()) {
        std::size_t end = head.find('\n', pos);
        if (end == std::string_view::npos) end = head.size();
        std::string_view line = head.substr(pos, end - pos);
        pos = end + 1;
        if (blank(line)) continue;
        if (line.front() == '%') return true;
        return line.size() > 4 && is_tag(line.substr(0, 4)) && line[4] == ';';
    }
    return false;
}

bool file_looks_like_log(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::string head(4096, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    return looks_like_log(head);
}

Scan to_scan(const WifiScan& s) {
    Scan out;
    out.reserve(s.readings.size());
    for (const auto& r : s.readings)
        if (valid_rss(r.rss_dbm)) out.push_back(Reading{"wifi", r.bssid, r.rss_dbm});
    return out;
}

std::vector<PressureSample> pressure_series(const Log& log) {
    std::vector<PressureSample> out;
    out.reserve(log.pres.size());
    for (const auto& p : log.pres) out.push_back({p.app_s, p.value});
    return out;
}

namespace {

// Each sample's time on the chosen clock (see Clock).
std::vector<double> times(const std::vector<Triad>& v, Clock clock) {
    std::vector<double> t(v.size());
    if (clock == Clock::app) {
        for (std::size_t i = 0; i < v.size(); ++i) t[i] = v[i].app_s;
        return t;
    }
    double shift = std::numeric_limits<double>::infinity();
    for (const auto& s : v) shift = std::min(shift, s.app_s - s.sensor_s);
    for (std::size_t i = 0; i < v.size(); ++i) t[i] = v[i].sensor_s + shift;
    return t;
}

}  // namespace

std::vector<AccelSample> accel_samples(const Log& log, Clock clock) {
    const auto t = times(log.acce, clock);
    std::vector<AccelSample> out;
    out.reserve(t.size());
    for (std::size_t i = 0; i < t.size(); ++i) out.push_back({t[i], log.acce[i].v.x, log.acce[i].v.y, log.acce[i].v.z});
    std::stable_sort(out.begin(), out.end(), [](const AccelSample& a, const AccelSample& b) { return a.t_s < b.t_s; });
    return out;
}

std::vector<ImuSample> imu_samples(const Log& log, Clock clock) {
    std::vector<ImuSample> out;
    out.reserve(log.acce.size() + log.gyro.size() + log.magn.size());
    auto add = [&](const std::vector<Triad>& v, ImuSensor sensor) {
        const auto t = times(v, clock);
        for (std::size_t i = 0; i < t.size(); ++i) out.push_back({t[i], sensor, v[i].v});
    };
    add(log.acce, ImuSensor::acc);
    add(log.gyro, ImuSensor::gyro);
    add(log.magn, ImuSensor::mag);
    std::stable_sort(out.begin(), out.end(), [](const ImuSample& a, const ImuSample& b) { return a.t_s < b.t_s; });
    return out;
}

}  // namespace locus::datasets::ipin
