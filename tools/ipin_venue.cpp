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
    // so it is about 3.2 m above floor 0 (docs/ipin-import.md discusses the sign).
    static const std::vector<FloorSpec> floors = {
        {0, "Floor 0", 0.0}, {-1, "Floor -1 (mezzanine)", 3.2}, {-2, "Floor -2", -5.7}};
    return floors;
}

std::string beacon_mac(int number) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "be:ac:20:23:00:%02x", number);
    return buf;
}

int logged_beacon(int csv_number) {
    if (csv_number == 2) return 3;
    if (csv_number == 3) return 2;
    return csv_number;
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
}

}  // namespace locus::tools::ipin
