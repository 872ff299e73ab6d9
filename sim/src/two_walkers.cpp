#include "sim/two_walkers.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>
#include <random>

#include "locus/motion/relative/angle_kalman.hpp"
#include "locus/motion/relative/range_fit.hpp"

namespace locus::sim {

namespace {

constexpr double kRad = std::numbers::pi / 180.0;

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const double at = q * double(v.size() - 1);
    const auto lo = std::size_t(std::floor(at));
    const auto hi = std::min(v.size() - 1, lo + 1);
    return v[lo] + (v[hi] - v[lo]) * (at - double(lo));
}

double bearing_deg(Point from, Point to) { return std::atan2(to.y - from.y, to.x - from.x) / kRad; }

}  // namespace

const char* method_name(RelativeMethod m) {
    switch (m) {
        case RelativeMethod::Rssi: return "rssi";
        case RelativeMethod::RssiMean: return "rssi-mean";
        case RelativeMethod::Exact: return "exact";
        case RelativeMethod::RssiKalman: return "rssi-kalman";
        case RelativeMethod::RssiKalmanAcoustic: return "rssi-kalman-acoustic";
        case RelativeMethod::RssiFit: return "rssi-fit";
        case RelativeMethod::BothFixes: return "both-fixes";
    }
    return "?";
}

TwoWalkerRun run_two_walkers(const TwoWalkerConfig& c, RelativeMethod m, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::normal_distribution<double> gauss(0.0, 1.0);

    // B anywhere on the circle around A's start; A's own frame (PDR) starts at the truth.
    const double b_angle = 180.0 * uniform(rng);
    const Point b{c.start_distance * std::cos(b_angle * kRad), c.start_distance * std::sin(b_angle * kRad)};
    Point truth{0, 0}, pdr{0, 0};
    double heading = b_angle + c.initial_spread_deg * uniform(rng);

    relative::DirectionEstimator est(c.estimator);
    relative::RangeKalman range_filter(c.range_kalman);
    std::deque<double> window;
    double last_reading = 0;  // the last RSSI distance before any smoothing
    // RssiFit: every PDR position with its RSSI distance, and the fitted B.
    std::vector<Point> walked;
    std::vector<double> ranges;
    std::optional<Point> fitted;
    const double first_heading = heading;
    TwoWalkerRun run;
    auto ranged = [&](double d) {
        if (m == RelativeMethod::Exact) return d;
        const double rss = ranging::rss_at(c.link.model, d) + c.shadowing_db * gauss(rng);
        if (m == RelativeMethod::Rssi) return relative::phone_distance(c.link, rss);
        if (m == RelativeMethod::RssiKalman || m == RelativeMethod::RssiKalmanAcoustic || m == RelativeMethod::RssiFit) {
            last_reading = relative::phone_distance(c.link, rss);
            range_filter.update_rssi(last_reading);
            if (m == RelativeMethod::RssiKalmanAcoustic && d <= c.acoustic_range)
                range_filter.update_direct(d + c.acoustic_sigma * gauss(rng), c.acoustic_sigma);
            return *range_filter.distance();
        }
        window.push_back(rss);
        while (int(window.size()) > std::max(1, c.rssi_window)) window.pop_front();
        const std::vector<double> w(window.begin(), window.end());
        return relative::phone_distance(c.link, w);
    };
    const double d0 = distance(truth, b);
    const double r0 = ranged(d0);
    run.distance_errors.push_back(std::abs(r0 - d0));
    est.step(pdr, r0);
    walked.push_back(pdr);
    ranges.push_back(last_reading);
    const int max_steps = int(c.seconds * c.step_hz);
    // BothFixes: the bearing between the two fused fixes, in the plan's frame (not PDR's).
    double fixes_distance = 0.0;  // between the last two fused fixes drawn
    const auto fixes_bearing = [&] {
        const Point fa{truth.x + c.fix_sigma * gauss(rng), truth.y + c.fix_sigma * gauss(rng)};
        const Point fb{b.x + c.fix_sigma * gauss(rng), b.y + c.fix_sigma * gauss(rng)};
        fixes_distance = distance(fa, fb);
        return bearing_deg(fa, fb);
    };
    std::optional<double> fixes_said;
    if (m == RelativeMethod::BothFixes) fixes_said = fixes_bearing();
    for (int k = 1; k <= max_steps; ++k) {
        // A's intended heading: the estimate's bearing once there is one.
        if (c.follow_estimate && fixes_said) {
            heading = *fixes_said;
        } else if (c.follow_estimate && m == RelativeMethod::RssiFit) {
            if (fitted) heading = bearing_deg(pdr, *fitted);
        } else if (c.follow_estimate) {
            if (auto target = est.target()) heading = bearing_deg(pdr, *target);
            else if (auto dir = est.direction_deg()) heading = *dir;
        }
        // The walker turns to `heading` as PDR sees it; the truth is off by the compass bias
        // and noise, and the step's length differs from the PDR's nominal one.
        const double true_heading = heading + c.heading_bias_deg + c.heading_sigma_deg * gauss(rng);
        const double true_len = c.step_length + c.step_length_sigma * gauss(rng);
        truth = {truth.x + true_len * std::cos(true_heading * kRad), truth.y + true_len * std::sin(true_heading * kRad)};
        pdr = {pdr.x + c.step_length * std::cos(heading * kRad), pdr.y + c.step_length * std::sin(heading * kRad)};
        range_filter.predict(c.step_length);
        ++run.steps;

        const double d = distance(truth, b);
        if (m == RelativeMethod::BothFixes) {
            fixes_said = fixes_bearing();
            run.distance_errors.push_back(std::abs(fixes_distance - d));  // no ranging: the distance is the fixes'
            if (d <= c.met_distance) {
                run.met = true;
                run.met_after_s = double(k) / c.step_hz;
                break;
            }
            run.errors_deg.push_back(std::abs(relative::wrap_deg(*fixes_said - bearing_deg(truth, b))));
            continue;
        }
        const double r = ranged(d);
        run.distance_errors.push_back(std::abs(r - d));
        est.step(pdr, r);
        if (m == RelativeMethod::RssiFit) {
            walked.push_back(pdr);
            ranges.push_back(last_reading);  // independent readings: the fit is the smoothing
            // The side of a straight walk is a coin toss to the ranges: the fit keeps the one
            // nearer where A first headed (it started roughly towards B).
            fitted = relative::fit_target(walked, ranges, pdr, r, fitted ? bearing_deg(pdr, *fitted) : first_heading);
        }
        if (d <= c.met_distance) {
            run.met = true;
            run.met_after_s = double(k) / c.step_hz;
            break;
        }
        std::optional<double> said;
        if (m == RelativeMethod::RssiFit) {
            if (fitted) said = bearing_deg(pdr, *fitted);
        } else if (auto target = est.target()) said = bearing_deg(pdr, *target);
        else said = est.direction_deg();
        if (!said) {
            ++run.steps_without_estimate;
            continue;
        }
        // The walker's frame is the PDR's: its bearing to B is compared with the true one.
        run.errors_deg.push_back(std::abs(relative::wrap_deg(*said - bearing_deg(truth, b))));
    }
    return run;
}

TwoWalkerSummary evaluate_two_walkers(const TwoWalkerConfig& c, RelativeMethod m, std::uint64_t seed, int runs) {
    TwoWalkerSummary s{m};
    std::vector<double> errors, met_after, dist_err;
    int steps = 0, without = 0, met = 0;
    for (int i = 0; i < runs; ++i) {
        const auto r = run_two_walkers(c, m, seed + std::uint64_t(i));
        errors.insert(errors.end(), r.errors_deg.begin(), r.errors_deg.end());
        dist_err.insert(dist_err.end(), r.distance_errors.begin(), r.distance_errors.end());
        steps += r.steps;
        without += r.steps_without_estimate;
        if (r.met) {
            ++met;
            met_after.push_back(r.met_after_s);
        }
    }
    s.runs = runs;
    s.median_error_deg = quantile(errors, 0.5);
    s.p90_error_deg = quantile(errors, 0.9);
    s.estimate_coverage = steps ? 1.0 - double(without) / double(steps) : 0.0;
    s.met_share = runs ? double(met) / double(runs) : 0.0;
    s.median_met_after_s = quantile(met_after, 0.5);
    s.median_distance_error = quantile(dist_err, 0.5);
    return s;
}

}  // namespace locus::sim
