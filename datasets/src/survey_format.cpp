#include "datasets/survey_format.hpp"

#include <charconv>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <unordered_map>

namespace locus::datasets::survey {

using nlohmann::json;

namespace {

constexpr double kMaxCoordinate = 1e7;  // the server's bound on x and y
constexpr std::size_t kMaxName = 200;

struct Bad : std::runtime_error {
    using std::runtime_error::runtime_error;
};

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

double number(std::string_view text, const char* what) {
    text = trim(text);
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v))
        throw Bad(std::string("'") + what + "' is not a number: \"" + std::string(text) + "\"");
    return v;
}

double coordinate(double v, const char* what) {
    if (!std::isfinite(v) || std::fabs(v) > kMaxCoordinate)
        throw Bad(std::string("'") + what + "' is outside [-1e7, 1e7] m");
    return v;
}

std::string rp_name(std::string_view raw) {
    const std::string_view name = trim(raw);
    if (name.empty()) throw Bad("'rp' is empty");
    if (name.size() > kMaxName) throw Bad("'rp' is longer than 200 characters");
    return std::string(name);
}

std::string type_of(std::string_view raw) {
    const std::string_view t = trim(raw);
    if (t.empty() || t == "wifi") return "wifi";
    if (t == "ble") return "ble";
    throw Bad("'type' must be wifi or ble, not \"" + std::string(t) + "\"");
}

Reading reading(std::string type, std::string_view bssid, double rss) {
    Reading r;
    r.type = std::move(type);
    r.bssid = Bssid(bssid);
    if (r.bssid.empty()) throw Bad("'bssid' is empty");
    if (r.bssid.str().size() > 64) throw Bad("'bssid' is longer than 64 characters");
    for (char c : r.bssid.str())
        if (static_cast<unsigned char>(c) < 0x20 || c == ',') throw Bad("'bssid' holds a control character or comma");
    if (!valid_rss(rss)) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", rss);  // 100, not 100.000000
        throw Bad(std::string("'rss' = ") + buf + " dBm is outside [-120, 0]");
    }
    r.rss = rss;
    return r;
}

bool same_point(Point a, Point b) { return std::fabs(a.x - b.x) < 1e-9 && std::fabs(a.y - b.y) < 1e-9; }

// Collects RPs in order of first appearance and checks that a name keeps its coordinates.
class Builder {
public:
    explicit Builder(SurveyFile& out) : out_(out) {}

    // Index of the RP, created if new; throws Bad on a coordinate conflict (nothing changed then).
    std::size_t rp(const std::optional<std::string>& name, std::optional<Point> at) {
        const std::string key = name ? *name : name_for(*at);
        auto it = index_.find(key);
        if (it == index_.end()) {
            out_.rps.push_back({key, at, {}});
            return index_.emplace(key, out_.rps.size() - 1).first->second;
        }
        auto& known = out_.rps[it->second];
        if (at && known.at && !same_point(*at, *known.at))
            throw Bad("RP '" + key + "' was given other coordinates on an earlier line");
        return it->second;
    }
    void fill_coordinates(std::size_t rp, std::optional<Point> at) {
        if (at && !out_.rps[rp].at) out_.rps[rp].at = at;
    }

private:
    SurveyFile& out_;
    std::unordered_map<std::string, std::size_t> index_;
};

std::optional<Point> point_of(std::optional<double> x, std::optional<double> y) {
    if (x.has_value() != y.has_value()) throw Bad("give both 'x' and 'y', or neither");
    if (!x) return std::nullopt;
    return Point{coordinate(*x, "x"), coordinate(*y, "y")};
}

// Calls use(line, line_no) for every line that is neither blank nor a '#' comment, trimmed and
// numbered from 1, until use returns false. Returns the number of the last line read.
template <typename Use>
std::size_t for_each_line(std::string_view text, Use use) {
    std::size_t line_no = 0;
    while (!text.empty()) {
        const auto nl = text.find('\n');
        const std::string_view line = trim(text.substr(0, nl));
        text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
        ++line_no;
        if (line.empty() || line.front() == '#') continue;
        if (!use(line, line_no)) break;
    }
    return line_no;
}

void parse_json_lines(std::string_view text, SurveyFile& out) {
    Builder builder(out);
    for_each_line(text, [&](std::string_view line, std::size_t line_no) {
        try {
            const json j = json::parse(line, nullptr, false);
            if (j.is_discarded()) throw Bad("not valid JSON");
            if (!j.is_object()) throw Bad("not a JSON object");
            for (const auto& [key, value] : j.items())
                if (key != "rp" && key != "x" && key != "y" && key != "t" && key != "readings")
                    throw Bad("unknown field '" + key + "'");
            std::optional<std::string> name;
            if (j.contains("rp")) {
                if (!j.at("rp").is_string()) throw Bad("'rp' must be a string");
                name = rp_name(j.at("rp").get<std::string>());
            }
            auto opt_number = [&](const char* key) -> std::optional<double> {
                if (!j.contains(key)) return std::nullopt;
                if (!j.at(key).is_number()) throw Bad(std::string("'") + key + "' must be a number");
                return j.at(key).get<double>();
            };
            const auto at = point_of(opt_number("x"), opt_number("y"));
            if (!name && !at) throw Bad("needs 'rp' or 'x' and 'y'");
            if (j.contains("t") && !j.at("t").is_number()) throw Bad("'t' must be a number (ms)");
            if (!j.contains("readings") || !j.at("readings").is_array() || j.at("readings").empty())
                throw Bad("'readings' must be a non-empty array");
            Scan scan;
            std::set<std::pair<std::string, std::string>> seen;
            for (const auto& r : j.at("readings")) {
                if (!r.is_object()) throw Bad("a reading must be an object {type, bssid, rss}");
                for (const auto& [key, value] : r.items())
                    if (key != "type" && key != "bssid" && key != "rss") throw Bad("unknown reading field '" + key + "'");
                if (!r.contains("bssid") || !r.at("bssid").is_string()) throw Bad("a reading needs a string 'bssid'");
                if (!r.contains("rss") || !r.at("rss").is_number()) throw Bad("a reading needs a number 'rss'");
                if (r.contains("type") && !r.at("type").is_string()) throw Bad("'type' must be a string");
                scan.push_back(reading(type_of(r.value("type", "wifi")), r.at("bssid").get<std::string>(), r.at("rss").get<double>()));
                if (!seen.emplace(scan.back().type, scan.back().bssid).second)
                    throw Bad("AP '" + scan.back().bssid.str() + "' appears twice in one scan");
            }
            const std::size_t rp = builder.rp(name, at);
            builder.fill_coordinates(rp, at);
            out.readings += scan.size();
            ++out.scans;
            out.rps[rp].scans.push_back(std::move(scan));
        } catch (const Bad& e) {
            out.errors.push_back({line_no, e.what()});
        }
        return true;
    });
}

std::vector<std::string_view> split(std::string_view line) {
    std::vector<std::string_view> cells;
    for (;;) {
        const auto comma = line.find(',');
        cells.push_back(trim(line.substr(0, comma)));
        if (comma == std::string_view::npos) break;
        line.remove_prefix(comma + 1);
    }
    return cells;
}

// Where the first byte that is not UTF-8 sits in a CSV line, as a message naming its cell.
std::optional<std::string> non_utf8_cell(const std::vector<std::string_view>& cells,
                                         const std::map<std::string, int>& column) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
        if (valid_utf8(cells[i])) continue;
        std::string name = "column " + std::to_string(i + 1);
        for (const auto& [n, c] : column)
            if (static_cast<std::size_t>(c) == i) name = "'" + n + "' (column " + std::to_string(i + 1) + ")";
        return "cell " + name + " holds bytes that are not UTF-8";
    }
    return std::nullopt;
}

void parse_csv(std::string_view text, SurveyFile& out) {
    Builder builder(out);
    std::map<std::string, int> column;
    bool have_header = false;
    std::size_t header_cells = 0;
    // (rp index, t) -> scan index within that RP, and the APs already in the scan.
    std::map<std::pair<std::size_t, std::string>, std::pair<std::size_t, std::set<std::pair<std::string, std::string>>>> scans;
    bool header_refused = false;
    const std::size_t last_line = for_each_line(text, [&](std::string_view line, std::size_t line_no) {
        const auto cells = split(line);
        if (!have_header) {
            if (const auto bad = non_utf8_cell(cells, column)) {
                out.errors.push_back({line_no, "the header's " + bad->substr(5)});
                header_refused = true;
                return false;
            }
            for (std::size_t i = 0; i < cells.size(); ++i) {
                const std::string name(cells[i]);
                if (name != "rp" && name != "x" && name != "y" && name != "t" && name != "type" && name != "bssid" &&
                    name != "rss") {
                    out.errors.push_back({line_no, "unknown column '" + name + "' (rp, x, y, t, type, bssid, rss)"});
                    continue;
                }
                column[name] = static_cast<int>(i);
            }
            const bool located = column.count("rp") || (column.count("x") && column.count("y"));
            if (!column.count("bssid") || !column.count("rss") || !column.count("t") || !located) {
                out.errors.push_back({line_no, "the header needs bssid, rss, t and rp or x,y"});
                header_refused = true;
                return false;  // without a usable header no line can be read
            }
            have_header = true;
            header_cells = cells.size();
            return true;
        }
        try {
            // A byte that is not UTF-8 cannot go into the JSON sent to the server; before, it
            // passed here and failed the whole RP's upload on every run.
            if (const auto bad = non_utf8_cell(cells, column)) throw Bad(*bad);
            if (cells.size() != header_cells)
                throw Bad("has " + std::to_string(cells.size()) + " cells, the header has " + std::to_string(header_cells));
            auto cell = [&](const char* name) -> std::optional<std::string_view> {
                const auto it = column.find(name);
                if (it == column.end() || static_cast<std::size_t>(it->second) >= cells.size()) return std::nullopt;
                return cells[static_cast<std::size_t>(it->second)];
            };
            std::optional<std::string> name;
            if (auto c = cell("rp"); c && !c->empty()) name = rp_name(*c);
            std::optional<double> x, y;
            if (auto c = cell("x"); c && !c->empty()) x = number(*c, "x");
            if (auto c = cell("y"); c && !c->empty()) y = number(*c, "y");
            const auto at = point_of(x, y);
            if (!name && !at) throw Bad("needs 'rp' or 'x' and 'y'");
            const std::string t(*cell("t"));
            if (t.empty()) throw Bad("'t' is empty");
            number(t, "t");
            Reading r = reading(type_of(cell("type").value_or("")), *cell("bssid"), number(*cell("rss"), "rss"));
            const std::size_t rp = builder.rp(name, at);
            auto [it, fresh] = scans.try_emplace({rp, t});
            if (!fresh && it->second.second.count({r.type, r.bssid}))
                throw Bad("AP '" + r.bssid.str() + "' appears twice in the scan at t=" + t);
            builder.fill_coordinates(rp, at);
            if (fresh) {
                it->second.first = out.rps[rp].scans.size();
                out.rps[rp].scans.emplace_back();
                ++out.scans;
            }
            it->second.second.emplace(r.type, r.bssid);
            out.rps[rp].scans[it->second.first].push_back(std::move(r));
            ++out.readings;
        } catch (const Bad& e) {
            out.errors.push_back({line_no, e.what()});
        }
        return true;
    });
    if (!have_header && !header_refused) out.errors.push_back({last_line, "no header line"});
}

}  // namespace

Format format_of(std::string_view path) {
    return path.size() >= 4 && path.substr(path.size() - 4) == ".csv" ? Format::Csv : Format::JsonLines;
}

bool valid_utf8(std::string_view s) {
    std::size_t i = 0;
    while (i < s.size()) {
        const auto c = static_cast<unsigned char>(s[i]);
        if (c < 0x80) {
            ++i;
            continue;
        }
        std::size_t len = 0;
        std::uint32_t cp = 0, min = 0;
        if ((c & 0xE0) == 0xC0) len = 2, cp = c & 0x1F, min = 0x80;
        else if ((c & 0xF0) == 0xE0) len = 3, cp = c & 0x0F, min = 0x800;
        else if ((c & 0xF8) == 0xF0) len = 4, cp = c & 0x07, min = 0x10000;
        else return false;
        if (i + len > s.size()) return false;
        for (std::size_t k = 1; k < len; ++k) {
            const auto cc = static_cast<unsigned char>(s[i + k]);
            if ((cc & 0xC0) != 0x80) return false;
            cp = (cp << 6) | (cc & 0x3F);
        }
        if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
        i += len;
    }
    return true;
}

std::string name_for(Point at) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "x%.2f_y%.2f", at.x, at.y);
    return buf;
}

SurveyFile parse(std::string_view text, Format format) {
    SurveyFile out;
    if (format == Format::Csv) parse_csv(text, out);
    else parse_json_lines(text, out);
    return out;
}

}  // namespace locus::datasets::survey
