#include "datasets/survey_sources.hpp"

#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

namespace locus::datasets::survey {

using nlohmann::json;

namespace {
constexpr double kEarthRadius = 6371008.8;  // mean radius, m

template <typename Fn>
void each_line(std::string_view text, Fn fn) {
    std::size_t line_no = 0;
    while (!text.empty()) {
        const auto nl = text.find('\n');
        std::string_view line = text.substr(0, nl);
        text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
        ++line_no;
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
        while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
        if (line.empty() || line.front() == '#') continue;
        fn(line_no, line);
    }
}

template <typename T>
bool parse_number(std::string_view s, T& out) {
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && ptr == s.data() + s.size();
}
}  // namespace

Find3Data parse_find3(std::string_view text) {
    Find3Data out;
    each_line(text, [&](std::size_t line_no, std::string_view line) {
        const json j = json::parse(line, nullptr, false);
        auto fail = [&](const std::string& m) { out.errors.push_back({line_no, m}); };
        if (j.is_discarded() || !j.is_object()) return fail("not a JSON object");
        if (!j.contains("l") || !j.at("l").is_string() || j.at("l").get<std::string>().empty())
            return fail("no location label 'l'");
        if (!j.contains("s") || !j.at("s").is_object()) return fail("no sensor object 's'");
        Scan scan;
        for (const auto& [source, readings] : j.at("s").items()) {
            if (source != "wifi" && source != "bluetooth") continue;  // FIND3 may carry other sensors
            if (!readings.is_object()) return fail("'s." + source + "' must be an object {bssid: rss}");
            for (const auto& [bssid, rss] : readings.items()) {
                if (!rss.is_number() || !valid_rss(rss.get<double>()))
                    return fail("'" + bssid + "' has an RSS outside [-120, 0] dBm");
                const std::string id = Bssid(bssid).str();
                if (id.empty()) return fail("an empty bssid");
                scan.push_back({source == "wifi" ? "wifi" : "ble", id, rss.get<double>()});
            }
        }
        if (scan.empty()) return fail("no wifi or bluetooth reading");
        const std::string label = j.at("l").get<std::string>();
        if (label.size() > 200) return fail("location label longer than 200 characters");
        if (out.family.empty() && j.contains("f") && j.at("f").is_string()) out.family = j.at("f").get<std::string>();
        out.readings += scan.size();
        ++out.scans;
        out.by_label[label].push_back(std::move(scan));
    });
    return out;
}

AnyplaceData parse_anyplace(std::string_view text) {
    AnyplaceData out;
    each_line(text, [&](std::size_t line_no, std::string_view line) {
        std::vector<std::string_view> f;
        while (!line.empty()) {
            const auto sp = line.find_first_of(" \t");
            f.push_back(line.substr(0, sp));
            if (sp == std::string_view::npos) break;
            line.remove_prefix(sp);
            while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
        }
        if (f.size() != 7) {
            out.errors.push_back({line_no, "expected 7 fields (timestamp lat lon heading bssid rss floor), got " + std::to_string(f.size())});
            return;
        }
        AnyplaceLine l;
        double heading = 0.0;
        if (!parse_number(f[0], l.timestamp) || !parse_number(f[1], l.lat) || !parse_number(f[2], l.lon) ||
            !parse_number(f[3], heading) || !parse_number(f[5], l.rss)) {
            out.errors.push_back({line_no, "a numeric field is not a number"});
            return;
        }
        if (std::fabs(l.lat) > 90 || std::fabs(l.lon) > 180) {
            out.errors.push_back({line_no, "latitude/longitude out of range"});
            return;
        }
        if (!valid_rss(l.rss)) {
            out.errors.push_back({line_no, "RSS outside [-120, 0] dBm"});
            return;
        }
        l.bssid = Bssid(f[4]);
        l.floor = std::string(f[6]);
        out.lines.push_back(std::move(l));
    });
    return out;
}

Point project(double lat, double lon, double lat0, double lon0) {
    constexpr double rad = std::numbers::pi / 180.0;
    return {(lon - lon0) * rad * kEarthRadius * std::cos(lat0 * rad), (lat - lat0) * rad * kEarthRadius};
}

}  // namespace locus::datasets::survey
