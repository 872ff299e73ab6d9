#include "sim/ranging_eval.hpp"

#include <cmath>
#include <map>
#include <utility>

#include "locus/motion/fusion/walk_runner.hpp"
#include "locus/motion/pdr/heading_convention.hpp"

namespace locus::sim {

fusion::RangingKalmanConfig RangingEvalConfig::default_kalman() { return fusion::ranging_kalman_config(); }

namespace {

std::vector<ranging::Heard> averaged(const Walk& walk, std::size_t from, std::size_t to) {
    std::map<std::string, std::pair<double, int>> sums;
    for (std::size_t i = from; i < to; ++i)
        for (const Reading& r : walk.anchor_scans[i].readings) {
            auto& [sum, n] = sums[r.bssid];
            sum += r.rss;
            ++n;
        }
    std::vector<ranging::Heard> heard;
    for (const Anchor& a : walk.anchors) {
        const auto it = sums.find(a.id);
        if (it != sums.end()) heard.push_back({a.tx, it->second.first / it->second.second});
    }
    return heard;
}

Fix as_fix(double t_s, const ranging::Fix& f, const fusion::RangingKalmanConfig& k) {
    return {t_s, f.at, f.used, fusion::ranging_measurement_noise(f, k)};
}

// Calls on_window(readings averaged per anchor, time of the window's last scan) for each
// consecutive window of window_s seconds holding a scan.
template <typename OnWindow>
void for_each_window(const Walk& walk, double window_s, OnWindow&& on_window) {
    if (walk.anchor_scans.empty() || window_s <= 0.0) return;
    std::size_t from = 0;
    for (double end = walk.anchor_scans.front().t_s + window_s - 1e-9; from < walk.anchor_scans.size(); end += window_s) {
        std::size_t to = from;
        while (to < walk.anchor_scans.size() && walk.anchor_scans[to].t_s <= end) ++to;
        if (to > from) on_window(averaged(walk, from, to), walk.anchor_scans[to - 1].t_s);
        from = to;
    }
}

}  // namespace

RangingFixes run_ranging(const Walk& walk, const RangingEvalConfig& config) {
    RangingFixes out;
    for_each_window(walk, config.window_s, [&](const std::vector<ranging::Heard>& heard, double t) {
        if (const auto f = ranging::trilaterate(heard, config.trilateration))
            out.trilateration.push_back(as_fix(t, *f, config.trilateration_kalman));
    });
    double residual_sum = 0.0;
    int residuals = 0;
    for_each_window(walk, config.multilateration_window_s, [&](std::vector<ranging::Heard> heard, double t) {
        const double offset = config.learn_offset && residuals > 0 ? residual_sum / residuals : 0.0;
        for (ranging::Heard& h : heard) h.rss -= offset;
        const auto f = ranging::multilaterate(heard, config.multilateration);
        if (!f) return;
        out.multilateration.push_back(as_fix(t, *f, config.kalman));
        for (const ranging::Heard& h : heard) {
            const double d = std::hypot(distance(h.tx.at, f->at), h.tx.dz);
            residual_sum += h.rss + offset - ranging::rss_at(h.tx.model, d);
            ++residuals;
        }
    });
    for (const Anchor& a : walk.anchors) out.anchors.push_back({a.id, a.tx});
    for (const WifiScan& scan : walk.anchor_scans) {
        std::vector<fusion::AnchorReading> readings;
        for (const Reading& r : scan.readings) readings.push_back({r.bssid, scan.t_s, r.rss});
        out.scans.push_back(std::move(readings));
    }
    return out;
}

namespace {

Track ekf_track(const std::vector<PdrStep>& steps, const RangingFixes& fixes, Point start,
                const fusion::RangingEkfConfig& config) {
    fusion::RangingEkf ekf(start, fixes.anchors, config);
    Track track{{0.0, start}};
    // The scans that heard an anchor, at their first reading's time; a step before a scan of
    // the same instant (fusion::kStepsFirst).
    std::vector<std::size_t> heard;
    std::vector<double> scan_t;
    for (std::size_t j = 0; j < fixes.scans.size(); ++j)
        if (!fixes.scans[j].empty()) heard.push_back(j), scan_t.push_back(fixes.scans[j].front().t_s);
    const std::vector<double> step_t = fusion::times_of(steps, &PdrStep::t_s);
    fusion::WalkHandlers handlers;
    handlers.step = [&](std::size_t i) {
        const PdrStep& s = steps[i];
        ekf.predict(pdr::step({0.0, 0.0}, s.length_m, s.heading_rad), s.t_s);
        track.push_back({s.t_s, ekf.position()});
    };
    handlers.fix = [&](std::size_t k) {
        const auto& scan = fixes.scans[heard[k]];
        ekf.update(scan);
        track.push_back({scan.front().t_s, ekf.position()});
    };
    fusion::run_walk({.step = step_t, .fix = scan_t}, handlers);
    return track;
}

}  // namespace

std::vector<NamedTrack> run_ranging_methods(const std::vector<PdrStep>& steps, const RangingFixes& fixes, Point start,
                                            const RangingEvalConfig& config,
                                            std::shared_ptr<const fusion::PlanWalkable> floor_plan) {
    std::vector<NamedTrack> out;
    auto fix_track = [](const std::vector<Fix>& fs) {
        Track t;
        for (const Fix& f : fs) t.push_back({f.t_s, f.at});
        return t;
    };
    out.push_back({"trilateration", fix_track(fixes.trilateration)});
    out.push_back({"multilateration", fix_track(fixes.multilateration)});
    out.push_back({"kalman_trilateration", kalman_track(steps, fixes.trilateration, start, config.trilateration_kalman.kalman)});
    out.push_back({"kalman_ranging", kalman_track(steps, fixes.multilateration, start, config.kalman.kalman,
                                                  config.kalman_fix_latency_s, std::move(floor_plan))});
    out.push_back({"ekf_ranging", ekf_track(steps, fixes, start, config.ekf)});
    return out;
}

}  // namespace locus::sim
