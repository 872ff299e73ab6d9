// The GetSensorData / IPIN logfile reader (datasets/ipin_log.*).
//
// Checks: parse_log() throws nothing but LogError, whose line is one the input has; what it
// returns holds only finite numbers (timestamps within ±1e10 s), normalised non-empty BSSIDs
// and MACs, WiFi scans that are non-empty, within 0.5 s and without a BSSID twice, App
// timestamps that never go back within a tag, and a truncated last line only when the input
// does not end with a newline; the IMU conversion is in time order. The same input with CRLF
// line ends reads the same.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>

#include "datasets/ipin_log.hpp"

namespace ipin = locus::datasets::ipin;

namespace {

[[noreturn]] void fail(const char* what, std::string_view text) {
    std::fprintf(stderr, "fuzz_ipin_log: %s\ninput (%zu bytes): %.*s\n", what, text.size(), static_cast<int>(text.size()),
                 text.data());
    std::abort();
}

void finite(double v, std::string_view text) {
    if (!std::isfinite(v)) fail("a non-finite number", text);
}

template <class V>
void in_order(const V& v, std::string_view text) {
    for (std::size_t i = 1; i < v.size(); ++i)
        if (v[i].app_s < v[i - 1].app_s) fail("AppTimestamps going back", text);
}

void check_id(const locus::Bssid& b, std::string_view text) {
    if (b.empty() || locus::Bssid(b.str()) != b) fail("an empty or unnormalised BSSID/MAC", text);
}

struct Result {
    bool threw = false;
    long error_line = 0;
    ipin::Log log;
};

Result run(std::string_view text) {
    Result r;
    try {
        r.log = ipin::parse_log(text, "fuzz.txt");
    } catch (const ipin::LogError& e) {
        r.threw = true;
        r.error_line = e.line();
        if (e.file() != "fuzz.txt") fail("an error naming another file", text);
    }
    return r;
}

void check(std::string_view text, const Result& r) {
    long lines = 0;
    for (char c : text) lines += c == '\n';
    if (!text.empty() && text.back() != '\n') ++lines;
    if (r.threw) {
        if (r.error_line < 1 || r.error_line > lines) fail("an error on a line the input does not have", text);
        return;
    }
    const auto& log = r.log;
    if (log.lines != lines) fail("a line count other than the input's", text);
    if (log.truncated_last_line && (text.empty() || text.back() == '\n')) fail("a truncated line in a terminated input", text);
    for (const auto* v : {&log.acce, &log.gyro, &log.magn}) {
        in_order(*v, text);
        for (const auto& s : *v) {
            finite(s.v.x, text), finite(s.v.y, text), finite(s.v.z, text);
            if (!(std::abs(s.app_s) <= 1e10 && std::abs(s.sensor_s) <= 1e10)) fail("a timestamp beyond ±1e10 s", text);
        }
    }
    for (const auto* v : {&log.pres, &log.ligh, &log.prox, &log.humi, &log.temp}) {
        in_order(*v, text);
        for (const auto& s : *v) finite(s.app_s, text), finite(s.sensor_s, text), finite(s.value, text);
    }
    for (const auto& s : log.ahrs) finite(s.yaw_deg, text), finite(s.q4, text);
    for (const auto& s : log.gnss)
        if (!(std::abs(s.lat_deg) <= 90.0 && std::abs(s.lon_deg) <= 180.0)) fail("a GNSS fix off the globe", text);
    for (const auto& s : log.posi)
        if (!(std::abs(s.lat_deg) <= 90.0 && std::abs(s.lon_deg) <= 180.0)) fail("a POSI off the globe", text);
    in_order(log.posi, text);
    in_order(log.wifi, text);
    for (const auto& scan : log.wifi) {
        if (scan.readings.empty()) fail("an empty WiFi scan", text);
        std::set<std::string> seen;
        for (const auto& w : scan.readings) {
            check_id(w.bssid, text);
            finite(w.rss_dbm, text);
            if (w.app_s < scan.app_s || w.app_s - scan.app_s > 0.5) fail("a reading outside its scan's 0.5 s", text);
            if (!seen.insert(w.bssid.str()).second) fail("a BSSID twice in one scan", text);
        }
        for (const auto& rd : ipin::to_scan(scan))
            if (!locus::valid_rss(rd.rss)) fail("an invalid RSS in a converted scan", text);
    }
    for (const auto& b : log.ble4) check_id(b.mac, text), finite(b.rssi_dbm, text);
    for (const auto& b : log.blue) check_id(b.mac, text);
    const auto imu = ipin::imu_samples(log);
    for (std::size_t i = 1; i < imu.size(); ++i)
        if (!(imu[i - 1].t_s <= imu[i].t_s)) fail("IMU samples out of order", text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const Result lf = run(text);
    check(text, lf);
    // CRLF line ends must read as LF ones, unless the input already holds '\r' of its own.
    if (text.find('\r') == std::string_view::npos && size < 4096) {
        std::string crlf;
        for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
        const Result cr = run(crlf);
        check(crlf, cr);
        if (cr.threw != lf.threw || cr.error_line != lf.error_line) fail("CRLF input read differently", text);
        if (!lf.threw && (cr.log.acce.size() != lf.log.acce.size() || cr.log.wifi.size() != lf.log.wifi.size() ||
                          cr.log.posi.size() != lf.log.posi.size() || cr.log.skipped != lf.log.skipped ||
                          cr.log.header.model != lf.log.header.model))
            fail("CRLF input read differently", text);
    }
    return 0;
}
