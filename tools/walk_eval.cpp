#include "walk_eval.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "locus/motion/fusion/heading_alignment.hpp"
#include "locus/motion/fusion/rules.hpp"
#include "locus/motion/fusion/walk_runner.hpp"
#include "locus/metrics.hpp"

namespace locus::tools::walks {

namespace putmc = datasets::putmc;

std::vector<PhoneStep> detect_steps(const putmc::Walk& walk, double until_s) {
    const auto accel = [](const putmc::AccSample& s) { return std::array{s.t_s, s.a.x, s.a.y, s.a.z}; };
    const auto azimuth_at = [&](double t) {
        return putmc::android_azimuth(sample_at(walk.orient, t, [](const putmc::OrientSample& o) { return o.t_s; }));
    };
    return detect_phone_steps(walk.acc, accel, azimuth_at, until_s);
}

std::vector<std::string_view> tuned_rule_names() { return {"midpoint", "midpoint_threshold", "proportional", "proportional2"}; }

std::vector<std::string> method_names(bool with_map, bool smooth) {
    std::vector<std::string> m = {"wifi", "pdr", "only_wifi", "midpoint", "midpoint_threshold", "proportional", "proportional2"};
    for (const auto& r : tuned_rule_names()) m.push_back(std::string(r) + "_tuned");
    m.push_back("kalman");
    if (with_map) m.push_back("particle");
    m.push_back("walk_pf_local");
    m.push_back("walk_pf");
    if (smooth) {
        m.push_back("rts_smoother");
        m.push_back("pf_smoother");
    }
    return m;
}

namespace {

// The estimate at each scan time from a track: the last point at or before it (a fix's
// point comes after the steps of the same instant, so it is the one taken).
std::vector<std::optional<Point>> at_scans(const sim::Track& track, const std::vector<double>& scan_t) {
    std::vector<std::optional<Point>> out(scan_t.size());
    std::size_t j = 0;
    std::optional<Point> last;
    for (std::size_t i = 0; i < scan_t.size(); ++i) {
        while (j < track.size() && track[j].t_s <= scan_t[i]) last = track[j++].at;
        out[i] = last;
    }
    return out;
}

// The same from a track run backwards in time: the first point at or after each scan time.
std::vector<std::optional<Point>> at_scans_backward(const sim::Track& reversed, const std::vector<double>& scan_t) {
    std::vector<std::optional<Point>> out(scan_t.size());
    std::size_t j = 0;
    std::optional<Point> last;
    for (std::size_t i = scan_t.size(); i-- > 0;) {
        while (j < reversed.size() && reversed[j].t_s >= scan_t[i]) last = reversed[j++].at;
        out[i] = last;
    }
    return out;
}

// walk_pf run from the walk's end to its start: each step taken backwards (azimuth + π), each
// fix met in reverse order. Its estimate at a scan uses the scan and everything after it.
sim::Track walk_pf_backward(const std::vector<PhoneStep>& phone, const std::vector<sim::Fix>& fx, double t0,
                            const std::optional<fusion::Walkable>& map, const fusion::WalkFilterConfig& wc) {
    fusion::WalkFilter wf(map, wc);
    sim::Track out;
    // The streams from their ends, times negated so the latest comes first; forwards a step at
    // a fix's time comes before the fix, so backwards after it (fusion::kFixesFirst).
    std::vector<double> step_t, fix_t;
    for (std::size_t i = phone.size(); i-- > 0;) step_t.push_back(-phone[i].t_s);
    for (std::size_t j = fx.size(); j-- > 0;) fix_t.push_back(-fx[j].t_s);
    bool before_start = false;  // a step before the first fix: nothing earlier is taken
    fusion::WalkHandlers handlers;
    handlers.fix = [&](std::size_t j) {
        if (before_start) return;
        const sim::Fix& f = fx[fx.size() - 1 - j];
        wf.fix(f.at, f.cov);
        out.push_back({f.t_s, wf.position()});
    };
    handlers.step = [&](std::size_t i) {
        const PhoneStep& s = phone[phone.size() - 1 - i];
        if (before_start) return;
        if (s.t_s < t0) {
            before_start = true;
            return;
        }
        wf.step(s.length_m, s.azimuth_rad + std::numbers::pi);
        if (wf.started()) out.push_back({s.t_s, wf.position()});
    };
    fusion::run_walk({.step = step_t, .fix = fix_t}, handlers, fusion::kFixesFirst);
    return out;
}

// Rauch–Tung–Striebel over the position Kalman filter (no walls): the forward pass, then
// backwards each state corrected with the next smoothed one. Offline: it uses the future.
sim::Track rts(const std::vector<sim::PdrStep>& steps, const std::vector<sim::Fix>& fixes, Point start,
               const fusion::KalmanConfig& kc) {
    struct Node {
        double t;
        Eigen::Vector2d x_pred, x_post;
        Eigen::Matrix2d p_pred, p_post;
    };
    std::vector<Node> nodes;
    Eigen::Vector2d x(start.x, start.y);
    Eigen::Matrix2d p = Eigen::Matrix2d::Identity() * kc.initial_sigma_m * kc.initial_sigma_m;
    nodes.push_back({0.0, x, x, p, p});
    fusion::WalkHandlers handlers;
    handlers.step = [&](std::size_t i) {
        const auto& s = steps[i];
        const double sig = kc.step_sigma_floor_m + kc.step_sigma_per_m * s.length_m;
        const Eigen::Vector2d u(s.length_m * std::sin(s.heading_rad), s.length_m * std::cos(s.heading_rad));
        const Eigen::Vector2d xp = x + u;
        const Eigen::Matrix2d pp = p + Eigen::Matrix2d::Identity() * sig * sig;
        x = xp, p = pp;
        nodes.push_back({s.t_s, xp, x, pp, p});
    };
    handlers.fix = [&](std::size_t j) {
        const auto& f = fixes[j];
        const Eigen::Matrix2d k = p * (p + f.cov).inverse();
        x = x + k * (Eigen::Vector2d(f.at.x, f.at.y) - x);
        p = (Eigen::Matrix2d::Identity() - k) * p;
        nodes.back().x_post = x, nodes.back().p_post = p;
        nodes.back().t = f.t_s;
    };
    const std::vector<double> step_t = fusion::times_of(steps, &sim::PdrStep::t_s), fix_t = fusion::times_of(fixes, &sim::Fix::t_s);
    fusion::run_walk({.step = step_t, .fix = fix_t}, handlers);  // a step before a fix of its instant
    std::vector<Eigen::Vector2d> xs(nodes.size());
    xs.back() = nodes.back().x_post;
    Eigen::Matrix2d ps = nodes.back().p_post;
    for (std::size_t n = nodes.size() - 1; n-- > 0;) {
        const Eigen::Matrix2d c = nodes[n].p_post * nodes[n + 1].p_pred.inverse();  // F = I
        xs[n] = nodes[n].x_post + c * (xs[n + 1] - nodes[n + 1].x_pred);
        ps = nodes[n].p_post + c * (ps - nodes[n + 1].p_pred) * c.transpose();
    }
    sim::Track out;
    for (std::size_t n = 0; n < nodes.size(); ++n) out.push_back({nodes[n].t, {xs[n].x(), xs[n].y()}});
    return out;
}

}  // namespace

WalkResult evaluate_walk(const putmc::Walk& walk, const std::vector<std::optional<sim::Fix>>& fixes, double floor_height_m,
                         const std::optional<fusion::Walkable>& map, const Config& config) {
    WalkResult r;
    r.name = walk.name;
    std::vector<double> scan_t;
    for (const auto& s : walk.scans) {
        scan_t.push_back(s.t_s);
        r.truth.push_back(putmc::to_floor(walk.truth_of(s), floor_height_m));
    }
    const double until = scan_t.empty() ? -INFINITY : scan_t.back();
    const std::vector<PhoneStep> phone = detect_steps(walk, until);
    r.steps = phone.size();

    // Fixes in time order; nothing is known before the first one.
    std::vector<sim::Fix> fx;
    for (const auto& f : fixes)
        if (f) fx.push_back(*f);
    r.fixes = fx.size();
    if (fx.empty()) {
        for (const auto& m : method_names(map.has_value(), config.smooth)) r.tracks.push_back({m, std::vector<std::optional<Point>>(scan_t.size())});
        return r;
    }
    const double t0 = fx.front().t_s;

    // One causal pass: the alignment learns from each fix and turns each step into the floor
    // frame with what it knew when the step came; the walk filter takes compass steps itself.
    fusion::HeadingAlignment align;
    fusion::WalkFilterConfig wc = config.walk_filter;
    fusion::WalkFilter wf(map, wc);
    sim::Track wf_track;
    std::vector<sim::PdrStep> steps;  // floor frame, from the first fix on
    fusion::WalkHandlers handlers;
    handlers.step = [&](std::size_t i) {
        const PhoneStep& s = phone[i];
        if (s.t_s < t0) return;
        align.add_step(s.length_m, s.azimuth_rad);
        steps.push_back({s.t_s, s.length_m, align.floor_heading(s.azimuth_rad), false});
        wf.step(s.length_m, s.azimuth_rad);
        wf_track.push_back({s.t_s, wf.position()});
    };
    handlers.fix = [&](std::size_t j) {
        const sim::Fix& f = fx[j];
        align.add_fix(f.at);
        if (align.pairs() >= 3) wf.hint(align.offset_rad(), align.mirrored());
        wf.fix(f.at, f.cov);
        wf_track.push_back({f.t_s, wf.position()});
    };
    const std::vector<double> phone_t = fusion::times_of(phone, &PhoneStep::t_s), fix_t = fusion::times_of(fx, &sim::Fix::t_s);
    fusion::run_walk({.step = phone_t, .fix = fix_t}, handlers);  // a step before a fix of its instant
    r.offset_deg = align.offset_rad() * 180.0 / std::numbers::pi;
    r.mirrored = align.mirrored();

    const Point start = fx.front().at;
    auto tracks = sim::run_methods(steps, fx, start, map, config.methods);
    // run_methods starts every track with the start at t = 0: it is the first fix's time.
    for (auto& t : tracks)
        for (auto& p : t.track) p.t_s = std::max(p.t_s, t0);
    // wifi: the last fix, held over a scan that matched nothing.
    for (const auto& name : tuned_rule_names()) {
        const auto rule = *fusion::parse_rule(name);
        tracks.push_back({std::string(name) + "_tuned", sim::rule_track(rule, steps, fx, start, config.tuned_rules)});
        for (auto& p : tracks.back().track) p.t_s = std::max(p.t_s, t0);
    }
    for (const auto& name : method_names(map.has_value(), config.smooth)) {
        const auto it = std::find_if(tracks.begin(), tracks.end(), [&](const sim::NamedTrack& t) { return t.method == name; });
        if (it != tracks.end()) r.tracks.push_back({name, at_scans(it->track, scan_t)});
    }
    r.tracks.push_back({"walk_pf_local", at_scans(wf_track, scan_t)});
    if (config.smooth) {
        r.tracks.push_back({"rts_smoother", at_scans(rts(steps, fx, start, config.methods.kalman), scan_t)});
        // Two-filter particle smoother: walk_pf forwards and backwards, averaged at each scan
        // (both hold the scan's own fix; the forward one everything before, the backward one
        // everything after). Offline: it uses the future.
        const auto fwd = r.tracks[r.tracks.size() - 2].at_scan;  // walk_pf_local
        fusion::WalkFilterConfig bc = wc;
        bc.particles = config.backward_particles;
        const auto bwd = at_scans_backward(walk_pf_backward(phone, fx, t0, map, bc), scan_t);
        std::vector<std::optional<Point>> both(scan_t.size());
        for (std::size_t k = 0; k < scan_t.size(); ++k) {
            if (fwd[k] && bwd[k]) both[k] = Point{(fwd[k]->x + bwd[k]->x) / 2, (fwd[k]->y + bwd[k]->y) / 2};
            else both[k] = fwd[k] ? fwd[k] : bwd[k];
        }
        r.tracks.push_back({"pf_smoother", both});
    }
    return r;
}

Stats stats_of(std::vector<double> e) {
    Stats s;
    s.n = e.size();
    if (e.empty()) return s;
    s.mean = metrics::mean(e);
    std::sort(e.begin(), e.end());
    s.median = metrics::percentile_interpolated(e, 0.5);
    s.p75 = metrics::percentile_interpolated(e, 0.75);
    s.p95 = metrics::percentile_interpolated(e, 0.95);
    return s;
}

std::vector<double> errors_of(const WalkResult& r, const std::string& method) {
    std::vector<double> out;
    for (const auto& t : r.tracks)
        if (t.method == method)
            for (std::size_t i = 0; i < t.at_scan.size(); ++i)
                if (t.at_scan[i]) out.push_back(distance(*t.at_scan[i], r.truth[i]));
    return out;
}

}  // namespace locus::tools::walks
