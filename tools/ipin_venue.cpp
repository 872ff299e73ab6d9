#include "ipin_venue.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <regex>
#include <set>
#include <stdexcept>

namespace locus::tools::ipin {

geo::Georeference venue_georeference() {
    geo::Georeference g;
    g.at = geo::LatLon{kOriginLat, kOriginLon};
    g.anchor = Point{kOriginX, kOriginY};
    g.bearing_deg = 0.0;
    return g;
}

const std::vector<FloorSpec>& venue_floors() {
    // 0.66 hPa between floors 0 and -2 is about 5.7 m (the README), 8.6 m per hPa; the
    // mezzanine's pressure is 0.37 hPa lower than floor 0's, and pressure falls with height,
    // so it is about 3.2 m above floor 0 (docs/ipin.md discusses the sign).
    static const std::vector<FloorSpec> floors = {
        {0, "Floor 0", 0.0}, {-1, "Floor -1 (mezzanine)", 3.2}, {-2, "Floor -2", -5.7}};
    return floors;
}

namespace {

std::string_view unquoted(std::string_view s) {
    while (!s.empty() && (s.back() == '\r' || s.back() == ' ')) s.remove_suffix(1);
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
    return s;
}

std::optional<double> number(std::string_view s) {
    double v = 0.0;
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

}  // namespace

std::vector<Beacon> parse_ble_locations(std::string_view text, const std::string& file) {
    std::vector<Beacon> out;
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
        Beacon b;
        b.line = line_no;
        b.name = std::string(cells[0]);
        const auto n = b.name.size() > 3 && b.name.compare(0, 3, "BLE") == 0 ? number(cells[0].substr(3)) : std::nullopt;
        if (!n || *n < 1 || *n > 255 || *n != std::floor(*n)) fail("'" + b.name + "' is not a beacon name BLE<n>, n in 1..255");
        b.number = static_cast<int>(*n);
        if (!seen.insert(b.number).second) fail("'" + b.name + "' is given twice");
        const auto lat = number(cells[1]), lon = number(cells[2]), floor = number(cells[3]);
        if (!lat || std::abs(*lat) > 90) fail("'Lat' is not a latitude: '" + std::string(cells[1]) + "'");
        if (!lon || std::abs(*lon) > 180) fail("'Lon' is not a longitude: '" + std::string(cells[2]) + "'");
        if (!floor || *floor != std::floor(*floor)) fail("'floor' is not a whole number: '" + std::string(cells[3]) + "'");
        b.lat = *lat;
        b.lon = *lon;
        b.floor = static_cast<int>(*floor);
        const auto& floors = venue_floors();
        if (std::none_of(floors.begin(), floors.end(), [&](const FloorSpec& f) { return f.level == b.floor; }))
            fail("floor " + std::to_string(b.floor) + " is not one of the venue's (0, -1, -2)");
        out.push_back(std::move(b));
    }
    if (!header) throw std::runtime_error(file + ": empty (no bleID,Lat,Lon,floor header)");
    return out;
}

std::string beacon_mac(int number) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "be:ac:20:23:00:%02x", number);
    return buf;
}

std::vector<std::string> trial_files(const std::string& dir, const std::vector<std::string>& globs) {
    namespace fs = std::filesystem;
    const fs::path trials = fs::path(dir) / "trials";
    std::error_code ec;
    if (!fs::is_directory(trials, ec)) throw std::runtime_error("'" + trials.string() + "' is not a folder");
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(trials)) {
        if (!e.is_regular_file()) continue;
        const std::string name = e.path().filename().string();
        if (std::any_of(globs.begin(), globs.end(), [&](const std::string& g) { return fnmatch(g.c_str(), name.c_str(), 0) == 0; }))
            out.push_back(e.path().string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::string trial_label(const std::string& path) {
    static const std::regex re(R"(TrainingTrial(\d+)_repetition(\d+))");
    const std::string stem = std::filesystem::path(path).stem().string();
    std::smatch m;
    if (!std::regex_search(stem, m, re)) return stem;
    std::string label(1, 'T');
    label += m[1].str();
    label += "_R";
    label += m[2].str();
    return label;
    return stem;
}

}  // namespace locus::tools::ipin
