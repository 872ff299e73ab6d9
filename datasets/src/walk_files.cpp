#include "datasets/walk_files.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <set>
#include <stdexcept>

namespace locus::datasets {

namespace {

std::string_view trimmed(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> split_commas(std::string_view line) {
    std::vector<std::string_view> out;
    for (;;) {
        const auto c = line.find(',');
        out.push_back(trimmed(line.substr(0, c)));
        if (c == std::string_view::npos) return out;
        line.remove_prefix(c + 1);
    }
}

std::optional<double> number(std::string_view s) {
    double v = 0.0;
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

std::string_view unquoted(std::string_view s) {
    while (!s.empty() && (s.back() == '\r' || s.back() == ' ')) s.remove_suffix(1);
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
    return s;
}

}  // namespace

std::vector<locus::survey::Landmark> parse_landmarks_csv(std::string_view text, const std::string& file) {
    std::vector<locus::survey::Landmark> out;
    long line_no = 0;
    int col_t = -1, col_floor = -1, col_x = -1, col_y = -1;
    std::size_t columns = 0;
    bool header = false;
    auto fail = [&](const std::string& m) { throw std::runtime_error(file + ":" + std::to_string(line_no) + ": " + m); };
    while (!text.empty()) {
        const auto nl = text.find('\n');
        const std::string_view line = trimmed(text.substr(0, nl));
        text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
        ++line_no;
        if (line.empty()) continue;
        const auto cells = split_commas(line);
        if (!header) {
            for (std::size_t i = 0; i < cells.size(); ++i) {
                const int c = static_cast<int>(i);
                if (cells[i] == "t") col_t = c;
                else if (cells[i] == "floor") col_floor = c;
                else if (cells[i] == "x") col_x = c;
                else if (cells[i] == "y") col_y = c;
            }
            if (col_t < 0 || col_floor < 0 || col_x < 0 || col_y < 0)
                fail("the header must name the columns t, floor, x and y");
            columns = cells.size();
            header = true;
            continue;
        }
        if (cells.size() != columns)
            fail(std::to_string(cells.size()) + " cells, the header has " + std::to_string(columns));
        locus::survey::Landmark l;
        const char* names[] = {"t", "floor", "x", "y"};
        const int cols[] = {col_t, col_floor, col_x, col_y};
        double v[4];
        for (int k = 0; k < 4; ++k) {
            const auto n = number(cells[static_cast<std::size_t>(cols[k])]);
            if (!n) {
                std::string m = names[k];
                m.insert(m.begin(), '\'');
                m += "' is not a finite number: '";
                m += cells[static_cast<std::size_t>(cols[k])];
                m += '\'';
                fail(m);
            }
            v[k] = *n;
        }
        if (v[1] != std::floor(v[1]) || std::abs(v[1]) > 1000) fail("'floor' must be a whole number within ±1000");
        l.t = v[0];
        l.floor = static_cast<int>(v[1]);
        l.at = Point{v[2], v[3]};
        if (!out.empty() && l.t < out.back().t) fail("landmarks must be in time order (t goes back)");
        out.push_back(l);
    }
    if (!header) throw std::runtime_error(file + ": no header line (t,floor,x,y)");
    if (out.empty()) throw std::runtime_error(file + ": no landmark");
    return out;
}

std::vector<IpinBeacon> parse_ipin_beacons(std::string_view text, const std::string& file) {
    std::vector<IpinBeacon> out;
    std::set<int> seen;
    long line_no = 0;
    bool header = false;
    while (!text.empty()) {
        const auto nl = text.find('\n');
        std::string_view line = text.substr(0, nl);
        text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
        ++line_no;
        auto fail = [&](const std::string& m) { throw std::runtime_error(file + ":" + std::to_string(line_no) + ": " + m); };
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
        if (line.empty()) continue;
        std::vector<std::string_view> cells;
        for (;;) {
            const auto c = line.find(',');
            cells.push_back(unquoted(line.substr(0, c)));
            if (c == std::string_view::npos) break;
            line.remove_prefix(c + 1);
        }
        if (!header) {
            if (cells.size() != 4 || cells[0] != "bleID" || cells[1] != "Lat" || cells[2] != "Lon" || cells[3] != "floor")
                fail("the header must be bleID,Lat,Lon,floor");
            header = true;
            continue;
        }
        if (cells.size() != 4) fail(std::to_string(cells.size()) + " cells, expected 4 (bleID,Lat,Lon,floor)");
        IpinBeacon b;
        b.line = line_no;
        b.name = std::string(cells[0]);
        const auto n = b.name.size() > 3 && b.name.compare(0, 3, "BLE") == 0 ? number(cells[0].substr(3)) : std::nullopt;
        if (!n || *n < 1 || *n > 255 || *n != std::floor(*n)) fail("'" + b.name + "' is not a beacon name BLE<n>, n in 1..255");
        b.number = static_cast<int>(*n);
        if (!seen.insert(b.number).second) fail("'" + b.name + "' is given twice");
        const auto lat = number(cells[1]), lon = number(cells[2]), floor = number(cells[3]);
        if (!lat || std::abs(*lat) > 90) fail("'Lat' is not a latitude: '" + std::string(cells[1]) + "'");
        if (!lon || std::abs(*lon) > 180) fail("'Lon' is not a longitude: '" + std::string(cells[2]) + "'");
        if (!floor || *floor != std::floor(*floor) || std::abs(*floor) > 1000) fail("'floor' is not a whole number: '" + std::string(cells[3]) + "'");
        b.lat = *lat;
        b.lon = *lon;
        b.floor = static_cast<int>(*floor);
        out.push_back(std::move(b));
    }
    if (!header) throw std::runtime_error(file + ": empty (no bleID,Lat,Lon,floor header)");
    return out;
}

}  // namespace locus::datasets
