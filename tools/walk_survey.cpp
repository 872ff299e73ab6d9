#include "walk_survey.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace locus::tools {

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

}  // namespace

std::vector<survey::Landmark> parse_landmarks_csv(std::string_view text, const std::string& file) {
    std::vector<survey::Landmark> out;
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
        survey::Landmark l;
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

std::vector<survey::Landmark> landmarks_of_posi(const datasets::ipin::Log& log, const ToFloor& to_floor,
                                                std::size_t& dropped) {
    std::vector<survey::Landmark> out;
    dropped = 0;
    for (const auto& p : log.posi) {
        const auto at = to_floor(p.floor, p.lat_deg, p.lon_deg);
        if (!at) {
            ++dropped;
            continue;
        }
        out.push_back({p.app_s, p.floor, *at});
    }
    return out;
}

void add_wifi_scans(const datasets::ipin::Log& log, Walk& walk) {
    for (const auto& s : log.wifi) {
        Scan scan = datasets::ipin::to_scan(s);
        if (scan.empty()) continue;
        walk.scan_times.push_back(s.app_s);
        walk.scans.push_back(std::move(scan));
    }
}

nlohmann::json WalkCounts::to_json() const {
    nlohmann::json per_floor = nlohmann::json::object();
    for (const auto& [f, n] : rps_per_floor)
        per_floor[std::to_string(f)] = {{"rps", n}, {"scans", scans_per_floor.count(f) ? scans_per_floor.at(f) : 0}};
    return {{"scans", scans},
            {"placed", placed},
            {"skipped_before_first", before_first},
            {"skipped_after_last", after_last},
            {"skipped_floor_change", floor_change},
            {"skipped_unmapped_floor", unmapped_floor},
            {"rps", rps},
            {"floors", per_floor}};
}

std::string cell_text(double cell_m) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", cell_m);
    return buf;
}

std::vector<RpJob> walk_jobs(const Walk& walk, const std::map<int, std::int64_t>& radiomap_of_floor, double cell_m,
                             WalkCounts& counts) {
    counts.scans += walk.scans.size();
    std::vector<RpJob> jobs;
    if (walk.landmarks.empty()) {
        counts.before_first += walk.scans.size();  // no landmark: nothing can be placed
        return jobs;
    }
    const auto placements = survey::place_scans(walk.landmarks, walk.scan_times);
    counts.before_first += placements.before_first;
    counts.after_last += placements.after_last;
    counts.floor_change += placements.floor_change;
    std::vector<survey::PositionedScan> mapped;
    for (const auto& p : placements.placed) {
        if (radiomap_of_floor.count(p.where.floor)) {
            mapped.push_back(p);
        } else {
            ++counts.unmapped_floor;
        }
    }
    counts.placed += mapped.size();
    const auto bins = survey::bin_along_path(mapped, cell_m);
    const std::string cell = cell_text(cell_m);
    const std::string upload_id = "walk-" + walk.content + "-" + cell;
    for (std::size_t k = 0; k < bins.size(); ++k) {
        const auto& b = bins[k];
        char number[24];
        std::snprintf(number, sizeof number, "%03zu", k + 1);
        RpJob job;
        job.radiomap_id = radiomap_of_floor.at(b.floor);
        job.name = walk.stem + " " + cell + "m #" + number;
        job.at = b.at;
        for (auto m : b.members) job.scans.push_back(walk.scans[mapped[m].scan]);
        job.upload_id = upload_id;
        job.source = walk.source;
        ++counts.rps_per_floor[b.floor];
        counts.scans_per_floor[b.floor] += b.members.size();
        jobs.push_back(std::move(job));
    }
    counts.rps += bins.size();
    return jobs;
}

}  // namespace locus::tools
