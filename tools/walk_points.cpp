#include "walk_points.hpp"

#include <filesystem>

#include "command_registry.hpp"
#include "datasets/putmc.hpp"
#include "sim/walk_io.hpp"

namespace locus::tools {

std::vector<LivePoint> walk_points(const std::string& path, double floor_height_m, double every_s) {
    std::vector<LivePoint> out;
    if (std::filesystem::is_directory(path)) {
        namespace putmc = datasets::putmc;
        const auto walk = putmc::read_walk(path);
        for (const auto& s : walk.scans)
            out.push_back({s.t_s - walk.scans.front().t_s, putmc::to_floor(walk.truth_of(s), floor_height_m)});
    } else {
        const auto walk = sim::load_walk(path);
        if (!walk.has_truth() || walk.imu.empty()) throw CommandError(path + ": the walk has no ground truth to replay");
        const double t0 = walk.imu.front().t_s, t1 = walk.imu.back().t_s;
        for (double t = t0; t <= t1; t += every_s)
            if (auto p = walk.truth_at(t)) out.push_back({t - t0, *p});
    }
    if (out.empty()) throw CommandError(path + ": no point of the walk to replay");
    return out;
}

}  // namespace locus::tools
