#include "walk_survey.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace locus::tools {

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
        // The content hash keeps two different files of one name (say, two folders' T01 walks
        // imported into one map) from merging into each other's RPs.
        job.name = walk.stem + " " + cell + "m #" + number + " " + walk.content.substr(0, 8);
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
