#include "datasets/putmc.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace locus::datasets::putmc {

namespace {

[[noreturn]] void fail(const std::string& file, long line, const std::string& what) {
    throw std::runtime_error(file + ":" + std::to_string(line) + ": " + what);
}

std::vector<std::string_view> fields(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const std::size_t b = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > b) out.push_back(line.substr(b, i - b));
    }
    return out;
}

// A finite number, or an error naming the file, line and what was expected.
double number(std::string_view s, const std::string& file, long line, const char* what) {
    double v = 0.0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size())
        fail(file, line, std::string(what) + " is not a number: '" + std::string(s) + "'");
    if (!std::isfinite(v)) fail(file, line, std::string(what) + " is not finite: '" + std::string(s) + "'");
    return v;
}

long long integer(std::string_view s, const std::string& file, long line, const char* what) {
    long long v = 0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size())
        fail(file, line, std::string(what) + " is not an integer: '" + std::string(s) + "'");
    return v;
}

bool blank(std::string_view line) { return line.find_first_not_of(" \t\r") == std::string_view::npos; }

// Calls on_line(fields, line number) for each non-blank line.
template <typename F>
void each_line(const std::string& text, F on_line) {
    std::size_t pos = 0;
    long n = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        ++n;
        const std::string_view line(text.data() + pos, end - pos);
        if (!blank(line)) on_line(line, n);
        pos = end + 1;
    }
}

void check_time(double t, double prev, const std::string& file, long line) {
    if (t < prev) fail(file, line, "timestamp goes back in time (" + std::to_string(t) + " s after " + std::to_string(prev) + " s): the file must be sorted");
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string join(const std::string& dir, const char* name) { return (std::filesystem::path(dir) / name).string(); }

void check_ids(const std::vector<WifiScan>& scans, const std::vector<Position>& positions, const std::string& wifi_file,
               const std::string& positions_file) {
    for (const auto& s : scans) {
        const bool known = std::any_of(positions.begin(), positions.end(), [&](const Position& p) { return p.id == s.loc_id; });
        if (!known)
            fail(wifi_file, s.line, "scan at point " + std::to_string(s.loc_id) + ", which " + positions_file + " does not list");
    }
}

Point find(const std::vector<Position>& positions, int id) {
    for (const auto& p : positions)
        if (p.id == id) return p.at;
    throw std::out_of_range("no position " + std::to_string(id));
}

}  // namespace

std::vector<AccSample> parse_acc(const std::string& text, const std::string& file) {
    std::vector<AccSample> out;
    double prev = -INFINITY;
    each_line(text, [&](std::string_view line, long n) {
        const auto f = fields(line);
        if (f.size() != 4) fail(file, n, "expected 'ts_ns ax ay az', got " + std::to_string(f.size()) + " fields");
        AccSample s;
        s.t_s = static_cast<double>(integer(f[0], file, n, "timestamp")) * 1e-9;
        check_time(s.t_s, prev, file, n);
        prev = s.t_s;
        s.a = {number(f[1], file, n, "ax"), number(f[2], file, n, "ay"), number(f[3], file, n, "az")};
        out.push_back(s);
    });
    return out;
}

std::vector<OrientSample> parse_orient(const std::string& text, const std::string& file) {
    std::vector<OrientSample> out;
    double prev = -INFINITY;
    each_line(text, [&](std::string_view line, long n) {
        const auto f = fields(line);
        if (f.size() != 6 && f.size() != 5)
            fail(file, n, "expected 'ts_ns qx qy qz qw heading_accuracy_rad', got " + std::to_string(f.size()) + " fields");
        OrientSample s;
        s.t_s = static_cast<double>(integer(f[0], file, n, "timestamp")) * 1e-9;
        check_time(s.t_s, prev, file, n);
        prev = s.t_s;
        s.qx = number(f[1], file, n, "qx");
        s.qy = number(f[2], file, n, "qy");
        s.qz = number(f[3], file, n, "qz");
        s.qw = number(f[4], file, n, "qw");
        if (f.size() == 6) s.accuracy_rad = number(f[5], file, n, "heading accuracy");
        const double norm = std::sqrt(s.qx * s.qx + s.qy * s.qy + s.qz * s.qz + s.qw * s.qw);
        if (norm < 0.5 || norm > 1.5) fail(file, n, "quaternion is not of unit length (|q| = " + std::to_string(norm) + ")");
        s.qx /= norm, s.qy /= norm, s.qz /= norm, s.qw /= norm;
        out.push_back(s);
    });
    return out;
}

std::vector<WifiScan> parse_wifi(const std::string& text, const std::string& file, bool timed) {
    std::vector<WifiScan> out;
    long long left = 0;  // readings still owed by the current block
    double prev = -INFINITY;
    each_line(text, [&](std::string_view line, long n) {
        if (left == 0) {
            const auto f = fields(line);
            if (f.size() != 3 || line.find('\t') != std::string_view::npos)
                fail(file, n, "expected a block header 'timestamp_ns locId nReadings'");
            WifiScan s;
            s.line = n;
            const long long ts = integer(f[0], file, n, "timestamp");
            s.t_s = timed ? static_cast<double>(ts) * 1e-9 : -1.0;
            if (timed) {
                if (ts < 0) fail(file, n, "a walk's scan needs a timestamp (got " + std::to_string(ts) + ")");
                check_time(s.t_s, prev, file, n);
                prev = s.t_s;
            }
            s.loc_id = static_cast<int>(integer(f[1], file, n, "locId"));
            left = integer(f[2], file, n, "nReadings");
            if (left < 0) fail(file, n, "negative nReadings");
            out.push_back(std::move(s));
            return;
        }
        // bssid <TAB> ssid <TAB> rss freq_MHz timestamp (the SSID may hold spaces or be empty)
        const auto t1 = line.find('\t');
        const auto t2 = t1 == std::string_view::npos ? t1 : line.find('\t', t1 + 1);
        if (t2 == std::string_view::npos)
            fail(file, n, "expected a reading 'bssid<TAB>ssid<TAB>rss freq ts' (" + std::to_string(left) +
                              " readings of the block at line " + std::to_string(out.back().line) + " missing?)");
        const auto rest = fields(line.substr(t2 + 1));
        if (rest.empty()) fail(file, n, "reading without an RSS");
        Reading r;
        r.bssid = line.substr(0, t1);
        if (r.bssid.empty()) fail(file, n, "reading without a BSSID");
        r.rss = number(rest[0], file, n, "rss");
        if (!valid_rss(r.rss)) fail(file, n, "rss " + std::string(rest[0]) + " dBm is out of range");
        out.back().readings.push_back(std::move(r));
        --left;
    });
    if (left > 0)
        fail(file, out.back().line, "truncated: the block promises " + std::to_string(out.back().readings.size() + left) +
                                        " readings, the file ends after " + std::to_string(out.back().readings.size()));
    return out;
}

std::vector<Position> parse_positions(const std::string& text, const std::string& file) {
    std::vector<Position> out;
    each_line(text, [&](std::string_view line, long n) {
        const auto f = fields(line);
        if (f.size() != 3) fail(file, n, "expected 'id x y', got " + std::to_string(f.size()) + " fields");
        Position p;
        p.id = static_cast<int>(integer(f[0], file, n, "id"));
        p.at = {number(f[1], file, n, "x"), number(f[2], file, n, "y")};
        for (const auto& q : out)
            if (q.id == p.id) fail(file, n, "id " + std::to_string(p.id) + " listed twice");
        out.push_back(p);
    });
    return out;
}

double parse_scale(const std::string& text, const std::string& file) {
    double scale = 0.0;
    int lines = 0;
    each_line(text, [&](std::string_view line, long n) {
        const auto f = fields(line);
        if (f.size() != 1 || ++lines > 1) fail(file, n, "expected one number, pixels per metre");
        scale = number(f[0], file, n, "pixels per metre");
        if (scale <= 0.0) fail(file, n, "pixels per metre must be positive");
    });
    if (lines == 0) fail(file, 1, "empty: expected pixels per metre");
    return scale;
}

Point Walk::truth_of(const WifiScan& s) const { return find(positions, s.loc_id); }
Point Survey::at_of(int loc_id) const { return find(positions, loc_id); }

Walk read_walk(const std::string& dir) {
    Walk w;
    w.name = std::filesystem::path(dir).lexically_normal().filename().string();
    if (w.name.empty()) w.name = std::filesystem::path(dir).lexically_normal().parent_path().filename().string();
    const auto acc = join(dir, "acc.map"), orient = join(dir, "orient.map"), wifi = join(dir, "wifi.map"),
               pos = join(dir, "positions.map");
    w.acc = parse_acc(read_text(acc), acc);
    w.orient = parse_orient(read_text(orient), orient);
    w.scans = parse_wifi(read_text(wifi), wifi, true);
    w.positions = parse_positions(read_text(pos), pos);
    check_ids(w.scans, w.positions, wifi, pos);
    if (w.acc.empty()) throw std::runtime_error(acc + ": no samples");
    if (w.orient.empty()) throw std::runtime_error(orient + ": no samples");
    return w;
}

Survey read_survey(const std::string& map_dir) {
    Survey s;
    const auto scale = join(map_dir, "scale.map"), wifi = join(map_dir, "wifi.map"), pos = join(map_dir, "positions.map");
    s.px_per_m = parse_scale(read_text(scale), scale);
    s.positions = parse_positions(read_text(pos), pos);
    s.scans = parse_wifi(read_text(wifi), wifi, false);
    check_ids(s.scans, s.positions, wifi, pos);
    return s;
}

std::vector<std::string> walk_dirs(const std::string& dir) {
    namespace fs = std::filesystem;
    if (fs::exists(fs::path(dir) / "acc.map")) return {dir};
    const fs::path trajs = fs::exists(fs::path(dir) / "trajs") ? fs::path(dir) / "trajs" : fs::path(dir);
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(trajs))
        if (e.is_directory() && fs::exists(e.path() / "acc.map")) out.push_back(e.path().string());
    // Natural order: traj2 before traj10.
    auto key = [](const std::string& p) {
        const std::string name = fs::path(p).filename().string();
        const auto d = name.find_first_of("0123456789");
        const auto e = d == std::string::npos ? d : name.find_first_not_of("0123456789", d);
        const long num = d == std::string::npos ? -1 : std::stol(name.substr(d, e == std::string::npos ? e : e - d));
        return std::pair{name.substr(0, d == std::string::npos ? name.size() : d), num};
    };
    std::sort(out.begin(), out.end(), [&](const std::string& a, const std::string& b) { return key(a) < key(b); });
    return out;
}

double android_azimuth(const OrientSample& q) {
    // Rotation matrix of the unit quaternion (row-major, device → ENU); getOrientation's
    // azimuth is atan2(R[0][1], R[1][1]): where the device's y axis points, from north to east.
    const double r01 = 2.0 * (q.qx * q.qy - q.qz * q.qw);
    const double r11 = 1.0 - 2.0 * (q.qx * q.qx + q.qz * q.qz);
    return std::atan2(r01, r11);
}

}  // namespace locus::datasets::putmc
