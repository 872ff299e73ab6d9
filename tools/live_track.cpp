#include "live_track.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <thread>

namespace locus::tools {

namespace {

double unix_now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

}  // namespace

api::TrackKey post_live(api::Client& client, const std::vector<LivePoint>& points, const LiveOptions& o, std::ostream& log) {
    const auto opened = client.open_track(o.map_id, o.label);
    log << "live track " << opened.key.id << " on map " << o.map_id << " (token " << opened.key.token << ")\n";
    if (points.empty()) return opened.key;
    const double walk_s = points.back().t_s - points.front().t_s;
    const auto wall_start = std::chrono::steady_clock::now();
    // At speed 0 the walk is dated so that its last fix is now; otherwise each fix is dated when it is sent.
    const double t_start = o.speed > 0 ? unix_now() : unix_now() - walk_s;
    std::vector<api::TrackFix> batch;
    std::optional<double> heading;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double rel = points[i].t_s - points.front().t_s;
        if (i > 0) {
            const double dx = points[i].at.x - points[i - 1].at.x, dy = points[i].at.y - points[i - 1].at.y;
            if (std::hypot(dx, dy) > 0.01) {  // standing still keeps the last heading
                double h = std::atan2(dx, dy) * 180.0 / std::numbers::pi;
                heading = h < 0 ? h + 360.0 : h;
            }
        }
        if (o.speed > 0)
            std::this_thread::sleep_until(wall_start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                           std::chrono::duration<double>(rel / o.speed)));
        const double t = t_start + (o.speed > 0 ? rel / o.speed : rel);
        batch.push_back({t, o.floor_id, points[i].at.x, points[i].at.y, o.accuracy_m, heading});
        if (o.speed > 0 || batch.size() == 1000 || i + 1 == points.size()) {
            client.post_fixes(opened.key, batch);
            batch.clear();
        }
    }
    if (o.close) client.close_track(opened.key);
    log << "posted " << points.size() << " fixes to track " << opened.key.id << (o.close ? ", closed it\n" : "\n");
    return opened.key;
}

}  // namespace locus::tools
