#include "datasets/uji_csv.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace locus::datasets::uji {

namespace {

constexpr std::string_view kTrailing[] = {"LONGITUDE", "LATITUDE", "FLOOR", "BUILDINGID", "SPACEID",
                                          "RELATIVEPOSITION", "USERID", "PHONEID", "TIMESTAMP"};
constexpr std::size_t kTrailingCount = std::size(kTrailing);

[[noreturn]] void fail(std::size_t line, const std::string& what) {
    throw std::runtime_error("UJIIndoorLoc CSV line " + std::to_string(line) + ": " + what);
}

std::string_view next_field(std::string_view& rest) {
    const auto comma = rest.find(',');
    std::string_view field = rest.substr(0, comma);
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    if (!field.empty() && field.back() == '\r') field.remove_suffix(1);
    return field;
}

template <typename T>
T number(std::string_view field, std::size_t line) {
    T value{};
    auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (ec != std::errc{} || end != field.data() + field.size())
        fail(line, "not a number: '" + std::string(field) + "'");
    return value;
}

}  // namespace

Data parse(std::string_view csv) {
    Data data;
    std::size_t line_no = 0;
    std::size_t columns = 0;
    std::vector<std::string_view> fields;
    while (!csv.empty()) {
        const auto nl = csv.find('\n');
        std::string_view line = csv.substr(0, nl);
        csv = nl == std::string_view::npos ? std::string_view{} : csv.substr(nl + 1);
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line.empty()) continue;
        std::string_view rest = line;
        if (line_no == 1) {
            std::vector<std::string> names;
            while (!rest.empty()) names.emplace_back(next_field(rest));
            for (auto& n : names)  // some copies of the file quote the header
                n.erase(std::remove(n.begin(), n.end(), '"'), n.end());
            if (names.size() <= kTrailingCount) fail(line_no, "too few columns for UJIIndoorLoc");
            for (std::size_t i = 0; i < kTrailingCount; ++i)
                if (names[names.size() - kTrailingCount + i] != kTrailing[i])
                    fail(line_no, "expected column " + std::string(kTrailing[i]));
            data.waps.assign(names.begin(), names.end() - kTrailingCount);
            columns = names.size();
            continue;
        }
        fields.clear();
        while (!rest.empty()) fields.push_back(next_field(rest));
        if (line.back() == ',') fields.emplace_back();  // a trailing empty field
        if (fields.size() != columns)
            fail(line_no, std::to_string(fields.size()) + " fields, expected " + std::to_string(columns));
        Row row;
        for (std::size_t c = 0; c < data.waps.size(); ++c) {
            const int v = number<int>(fields[c], line_no);
            // 100 is "not detected"; anything else out of range is a bad sample (docs/spec.md §2.7).
            if (v != kNotDetected && valid_rss(v)) row.heard.emplace_back(static_cast<std::uint16_t>(c), v);
        }
        const std::string_view* f = fields.data() + data.waps.size();
        row.longitude = number<double>(f[0], line_no);
        row.latitude = number<double>(f[1], line_no);
        row.floor = number<int>(f[2], line_no);
        row.building = number<int>(f[3], line_no);
        row.space_id = number<int>(f[4], line_no);
        row.relative_position = number<int>(f[5], line_no);
        row.user_id = number<int>(f[6], line_no);
        row.phone_id = number<int>(f[7], line_no);
        row.timestamp = number<long long>(f[8], line_no);
        data.rows.push_back(std::move(row));
    }
    if (line_no == 0) throw std::runtime_error("UJIIndoorLoc CSV: empty file");
    return data;
}

Data read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    const std::string text = std::move(buffer).str();
    return parse(text);
}

std::string bssid_of(const Data& data, std::uint16_t column) { return Bssid(data.waps.at(column)).str(); }

Scan scan_of(const Data& data, const Row& row) {
    Scan scan;
    scan.reserve(row.heard.size());
    for (const auto& [column, rss] : row.heard) scan.push_back(Reading{"wifi", bssid_of(data, column), rss});
    return scan;
}

std::vector<ReferencePointGroup> group_reference_points(const Data& data, const std::vector<std::size_t>& rows) {
    using Key = std::tuple<int, int, double, double>;
    std::map<Key, ReferencePointGroup> groups;
    auto add = [&](std::size_t r) {
        const Row& row = data.rows[r];
        auto [it, inserted] = groups.try_emplace(Key{row.building, row.floor, row.longitude, row.latitude});
        if (inserted) {
            it->second.building = row.building;
            it->second.floor = row.floor;
            it->second.longitude = row.longitude;
            it->second.latitude = row.latitude;
        }
        it->second.rows.push_back(r);
    };
    if (rows.empty())
        for (std::size_t r = 0; r < data.rows.size(); ++r) add(r);
    else
        for (auto r : rows) add(r);

    std::vector<ReferencePointGroup> out;
    out.reserve(groups.size());
    std::vector<RssStats> stats(data.waps.size());
    for (auto& [key, g] : groups) {
        std::fill(stats.begin(), stats.end(), RssStats{});
        for (auto r : g.rows)
            for (const auto& [column, rss] : data.rows[r].heard) stats[column].add(rss);
        for (std::size_t c = 0; c < stats.size(); ++c)
            if (stats[c].count > 0)
                g.measurements.push_back(Measurement{"wifi", bssid_of(data, static_cast<std::uint16_t>(c)), stats[c]});
        out.push_back(std::move(g));
    }
    return out;
}

std::vector<match::IndexedRp> indexed_rps(const Data& data, const std::vector<std::size_t>& rows) {
    std::vector<match::IndexedRp> out;
    for (auto& g : group_reference_points(data, rows)) {
        match::IndexedRp rp;
        rp.rp.id = static_cast<long long>(out.size()) + 1;
        rp.rp.at = Point{g.longitude, g.latitude};
        rp.rp.scans = static_cast<std::int64_t>(g.rows.size());
        rp.rp.measurements = std::move(g.measurements);
        rp.floor_id = floor_id(g.building, g.floor);
        rp.building_id = g.building;
        out.push_back(std::move(rp));
    }
    return out;
}

namespace {
// Calls f(row index) for the given rows, or for every row when none are given.
template <typename F>
void for_rows(const Data& data, const std::vector<std::size_t>& rows, F&& f) {
    if (rows.empty())
        for (std::size_t r = 0; r < data.rows.size(); ++r) f(r);
    else
        for (auto r : rows) f(r);
}
}  // namespace

std::vector<match::IndexedRp> raw_rps(const Data& data, const std::vector<std::size_t>& rows) {
    std::vector<match::IndexedRp> out;
    for_rows(data, rows, [&](std::size_t r) {
        const Row& row = data.rows[r];
        match::IndexedRp rp;
        rp.rp.id = static_cast<long long>(out.size()) + 1;
        rp.rp.at = Point{row.longitude, row.latitude};
        rp.rp.scans = 1;
        for (const auto& [column, rss] : row.heard) {
            RssStats stats;
            stats.add(rss);
            rp.rp.measurements.push_back(Measurement{"wifi", bssid_of(data, column), stats});
        }
        rp.floor_id = floor_id(row.building, row.floor);
        rp.building_id = row.building;
        out.push_back(std::move(rp));
    });
    return out;
}

std::optional<double> min_rss(const Data& data, const std::vector<std::size_t>& rows) {
    std::optional<double> low;
    for_rows(data, rows, [&](std::size_t r) {
        for (const auto& reading : data.rows[r].heard)
            if (!low || reading.second < *low) low = reading.second;
    });
    return low;
}

}  // namespace locus::datasets::uji
