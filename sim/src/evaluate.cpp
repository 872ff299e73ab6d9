#include "sim/evaluate.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "locus/motion/fusion/walk_runner.hpp"
#include "locus/metrics.hpp"
#include "locus/motion/pdr/heading_convention.hpp"

namespace locus::sim {

std::vector<PdrStep> run_pdr(const Walk& walk, pdr::PipelineConfig config) {
    config.start = walk.start;
    config.start_heading_rad = walk.start_heading_rad;
    config.heading.north_offset_deg = walk.north_offset_deg;
    if (walk.earth_field_ut) config.heading.expected_field_ut = *walk.earth_field_ut;
    pdr::Pipeline pipeline(config);
    std::vector<PdrStep> steps;
    for (const ImuSample& s : walk.imu) {
        pipeline.push_gyro(s.t_s, s.gyro);
        pipeline.push_mag(s.t_s, s.mag);
        if (auto p = pipeline.push_accel(s.t_s, s.acc)) steps.push_back({p->t_s, p->step_length_m, p->heading_rad, p->magnetic_disturbance});
    }
    return steps;
}

match::Index build_index(const Walk& walk) {
    std::vector<match::IndexedRp> rps;
    long long id = 1;
    for (const SurveyPoint& sp : walk.survey) {
        match::IndexedRp r;
        r.rp.id = id++;
        r.rp.name = sp.name;
        r.rp.at = sp.at;
        r.rp.scans = static_cast<std::int64_t>(sp.scans.size());
        r.rp.measurements = aggregate_scans(sp.scans);
        rps.push_back(std::move(r));
    }
    return match::Index::build(rps);
}

Fix make_fix(double t_s, int aps, const match::Result& result, int k, double sigma_floor_m) {
    std::vector<Point> spread;
    for (const match::Candidate& c : result.candidates) {
        if (static_cast<int>(spread.size()) >= std::max(1, k)) break;
        spread.push_back(c.at);
    }
    if (spread.empty()) spread.push_back(result.at);
    return {t_s, result.at, aps, fusion::fix_covariance(spread, {}, sigma_floor_m)};
}

std::vector<Fix> run_matcher(const Walk& walk, const match::Index& index, const EvalConfig& config) {
    std::vector<Fix> fixes;
    match::Workspace workspace;
    for (const WifiScan& scan : walk.scans) {
        const match::Query q = match::Query::from_scans({scan.readings});
        if (q.aps.empty()) continue;
        const auto result = match::localize(index, q, config.algorithm, config.match_options, workspace);
        if (!result) continue;
        fixes.push_back(make_fix(scan.t_s, static_cast<int>(q.aps.size()), *result, config.match_options.k,
                                 config.fix_sigma_floor_m));
    }
    return fixes;
}

namespace {

// Walks steps and fixes in time order, a step before a fix of the same instant
// (fusion::kStepsFirst).
template <typename OnStep, typename OnFix>
void replay_events(const std::vector<PdrStep>& steps, const std::vector<Fix>& fixes, OnStep on_step, OnFix on_fix) {
    const std::vector<double> step_t = fusion::times_of(steps, &PdrStep::t_s), fix_t = fusion::times_of(fixes, &Fix::t_s);
    fusion::WalkHandlers handlers;
    handlers.step = [&](std::size_t i) { on_step(steps[i]); };
    handlers.fix = [&](std::size_t i) { on_fix(fixes[i]); };
    fusion::run_walk({.step = step_t, .fix = fix_t}, handlers);
}

}  // namespace

Point latency_corrected(const Fix& f, const std::vector<PdrStep>& steps, double latency_s) {
    Point at = f.at;
    if (latency_s <= 0.0) return at;
    for (const PdrStep& s : steps) {
        if (s.t_s <= f.t_s - latency_s) continue;
        if (s.t_s > f.t_s) break;
        at = pdr::step(at, s.length_m, s.heading_rad);
    }
    return at;
}

Track kalman_track(const std::vector<PdrStep>& steps, const std::vector<Fix>& fixes, Point start,
                   const fusion::KalmanConfig& config, double fix_latency_s,
                   std::shared_ptr<const fusion::PlanWalkable> floor_plan) {
    fusion::KalmanFilter kf(start, config, std::move(floor_plan));
    Track track{{0.0, start}};
    replay_events(
        steps, fixes,
        [&](const PdrStep& s) {
            const Point d = pdr::step({0.0, 0.0}, s.length_m, s.heading_rad);
            kf.predict(d, s.magnetic_disturbance);
            track.push_back({s.t_s, kf.position()});
        },
        [&](const Fix& f) {
            kf.update(latency_corrected(f, steps, fix_latency_s), f.cov);
            track.push_back({f.t_s, kf.position()});
        });
    return track;
}

Track rule_track(fusion::Rule rule, const std::vector<PdrStep>& steps, const std::vector<Fix>& fixes, Point start,
                 const fusion::RuleParams& params) {
    Track track{{0.0, start}};
    Point pos = start;   // the PDR track, continued from each fused position
    Point prev = start;  // the previous fused position (the known start before any fix)
    std::optional<Point> prev_wifi;
    replay_events(
        steps, fixes,
        [&](const PdrStep& s) {
            pos = pdr::step(pos, s.length_m, s.heading_rad);
            track.push_back({s.t_s, pos});
        },
        [&](const Fix& f) {
            fusion::FusionInput in{pos, f.at, prev, f.aps, prev_wifi};
            pos = fusion::fuse(rule, in, params);
            prev = pos;
            prev_wifi = f.at;
            track.push_back({f.t_s, pos});
        });
    return track;
}

std::vector<NamedTrack> run_methods(const std::vector<PdrStep>& steps, const std::vector<Fix>& fixes, Point start,
                                    const std::optional<fusion::Walkable>& map, const EvalConfig& config) {
    std::vector<NamedTrack> out;

    Track pdr_track{{0.0, start}};
    Point pos = start;
    for (const PdrStep& s : steps) {
        pos = pdr::step(pos, s.length_m, s.heading_rad);
        pdr_track.push_back({s.t_s, pos});
    }
    out.push_back({"pdr", std::move(pdr_track)});

    Track wifi_track;
    for (const Fix& f : fixes) wifi_track.push_back({f.t_s, f.at});
    out.push_back({"wifi", std::move(wifi_track)});

    for (fusion::Rule r : fusion::all_rules())
        out.push_back({std::string(fusion::to_string(r)), rule_track(r, steps, fixes, start, config.rules)});

    // Map matching needs a floor plan (walls, door gaps): rooms and doors leave it free.
    out.push_back({"kalman", kalman_track(steps, fixes, start, config.kalman, config.kalman_fix_latency_s,
                                          map ? map->floor_plan : nullptr)});

    if (map) {
        fusion::ParticleFilter pf(*map, start, config.particle);
        Track track{{0.0, start}};
        replay_events(
            steps, fixes,
            [&](const PdrStep& s) {
                pf.predict(s.length_m, s.heading_rad, s.magnetic_disturbance);
                track.push_back({s.t_s, pf.position()});
            },
            [&](const Fix& f) {
                pf.update(latency_corrected(f, steps, config.particle_fix_latency_s), f.cov);
                track.push_back({f.t_s, pf.position()});
            });
        out.push_back({"particle", std::move(track)});
    }
    return out;
}

Score score(const NamedTrack& nt, const Walk& walk) {
    Score sc;
    sc.method = nt.method;
    std::vector<double> errors;
    for (const TrackPoint& p : nt.track)
        if (auto truth = walk.truth_at(p.t_s)) errors.push_back(distance(p.at, *truth));
    sc.points = errors.size();
    if (errors.empty()) return sc;
    sc.mean_error_m = metrics::mean(errors);
    sc.final_error_m = errors.back();
    std::vector<double> sorted = errors;
    std::sort(sorted.begin(), sorted.end());
    sc.p95_error_m = metrics::percentile_nearest_rank(sorted, 0.95);
    return sc;
}

std::vector<Score> evaluate(const Walk& walk, const EvalConfig& config) {
    if (!walk.has_truth()) throw std::invalid_argument("the walk has no ground truth to evaluate against");
    const std::vector<PdrStep> steps = run_pdr(walk);
    const match::Index index = build_index(walk);
    const std::vector<Fix> fixes = run_matcher(walk, index, config);
    std::vector<Score> scores;
    for (const NamedTrack& t : run_methods(steps, fixes, walk.start, walk.map, config)) scores.push_back(score(t, walk));
    return scores;
}

}  // namespace locus::sim
