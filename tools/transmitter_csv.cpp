#include "transmitter_csv.hpp"

#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "locus/ranging/beacon_id.hpp"

namespace locus::tools {

using nlohmann::json;

namespace {

// One CSV record: commas separate, double quotes may wrap a cell ("" is a quote inside).
std::vector<std::string> cells_of(std::string_view line) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                cells.back() += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                cells.back() += c;
            }
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            cells.emplace_back();
        } else {
            cells.back() += c;
        }
    }
    for (auto& cell : cells) {  // surrounding spaces are layout, not content
        const auto b = cell.find_first_not_of(" \t\r");
        const auto e = cell.find_last_not_of(" \t\r");
        cell = b == std::string::npos ? "" : cell.substr(b, e - b + 1);
    }
    return cells;
}

bool number_of(const std::string& s, double& out) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(out);
}

const std::set<std::string> kNumbers{"x", "y", "z", "tx_power", "path_loss_exponent", "wall_attenuation", "major", "minor"};
const std::set<std::string> kKnown{"name", "type", "bssid", "x", "y", "z", "tx_power", "path_loss_exponent",
                                   "wall_attenuation", "uuid", "major", "minor", "namespace", "instance"};

}  // namespace

TransmitterRows parse_transmitter_csv(std::string_view text) {
    TransmitterRows out;
    std::vector<std::string> header;
    int line_no = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
        auto end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        const std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        if (line.find_first_not_of(" \t\r") == std::string_view::npos) continue;
        auto cells = cells_of(line);
        if (header.empty()) {
            header = cells;
            std::set<std::string> seen;
            for (const auto& h : header) {
                if (!kKnown.count(h)) out.errors.push_back("line " + std::to_string(line_no) + ": unknown column '" + h + "'");
                if (!seen.insert(h).second) out.errors.push_back("line " + std::to_string(line_no) + ": column '" + h + "' twice");
            }
            for (const char* required : {"x", "y", "tx_power"})
                if (!seen.count(required)) out.errors.push_back("the header has no '" + std::string(required) + "' column");
            if (!out.errors.empty()) return out;
            continue;
        }
        const std::string where = "line " + std::to_string(line_no) + ": ";
        if (cells.size() != header.size()) {
            out.errors.push_back(where + std::to_string(cells.size()) + " cells, the header has " + std::to_string(header.size()));
            continue;
        }
        std::map<std::string, std::string> row;
        for (std::size_t i = 0; i < cells.size(); ++i)
            if (!cells[i].empty()) row[header[i]] = cells[i];
        json body = json::object();
        bool bad = false;
        for (const auto& [key, value] : row) {
            if (!kNumbers.count(key)) continue;
            double v = 0;
            if (!number_of(value, v)) {
                out.errors.push_back(where + "'" + key + "' = '" + value + "' is not a number");
                bad = true;
            } else if (key == "major" || key == "minor") {
                if (v != std::floor(v) || v < 0 || v > 65535) {
                    out.errors.push_back(where + "'" + key + "' must be an integer in [0, 65535]");
                    bad = true;
                }
            } else {
                body[key] = v;
            }
        }
        for (const char* required : {"x", "y", "tx_power"})
            if (!row.count(required)) {
                out.errors.push_back(where + "no '" + required + "'");
                bad = true;
            }
        const bool ibeacon = row.count("uuid") || row.count("major") || row.count("minor");
        const bool eddystone = row.count("namespace") || row.count("instance");
        const int forms = int(row.count("bssid") > 0) + int(ibeacon) + int(eddystone);
        if (forms != 1) {
            out.errors.push_back(where + "give one of bssid, uuid/major/minor and namespace/instance");
            bad = true;
        }
        if (bad) continue;
        if (row.count("name")) body["name"] = row["name"];
        // A beacon given by its parts gets its id here, as the server would build it, so the
        // import can tell which transmitters the floor already has.
        std::optional<std::string> id;
        if (row.count("bssid")) {
            id = row["bssid"];
        } else if (ibeacon) {
            double major = -1, minor = -1;
            if (row.count("major")) number_of(row["major"], major);
            if (row.count("minor")) number_of(row["minor"], minor);
            id = ranging::ibeacon_id(row.count("uuid") ? row["uuid"] : "", static_cast<std::int64_t>(major),
                                     static_cast<std::int64_t>(minor));
            if (!id) out.errors.push_back(where + "uuid, major and minor do not make an iBeacon id (32 hex digits; 0 to 65535)");
        } else {
            id = ranging::eddystone_id(row.count("namespace") ? row["namespace"] : "", row.count("instance") ? row["instance"] : "");
            if (!id) out.errors.push_back(where + "namespace and instance do not make an Eddystone id (20 and 12 hex digits)");
        }
        if (!id) continue;
        body["bssid"] = *id;
        body["type"] = row.count("type") ? row["type"] : (row.count("bssid") ? "wifi" : "ble");
        out.bodies.push_back(std::move(body));
        out.lines.push_back(line_no);
    }
    if (header.empty()) out.errors.push_back("the file is empty (it needs a header row)");
    return out;
}

}  // namespace locus::tools
