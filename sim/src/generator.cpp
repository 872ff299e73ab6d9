#include "sim/generator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "locus/motion/pdr/heading_convention.hpp"
#include "sim/environment.hpp"

namespace locus::sim {

namespace {

constexpr double kG = 9.80665;
constexpr double kPi = std::numbers::pi;

struct PlannedStep {
    double t0, duration, s0, length, amplitude;
};

pdr::Vec3 to_vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Heading along the path (docs/spec.md §2.2: clockwise from +y), turning smoothly over the metre
// around each corner as a walker does.
class HeadingProfile {
public:
    explicit HeadingProfile(const std::vector<Point>& path) {
        double s = 0.0;
        for (std::size_t i = 1; i < path.size(); ++i) {
            const double h = std::atan2(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
            if (i == 1) start_ = h;
            else turns_.push_back({s, pdr::wrap_angle(h - last_)});
            last_ = h;
            s += distance(path[i - 1], path[i]);
        }
    }
    double at(double s) const {
        double h = start_;
        for (const auto& [corner, turn] : turns_) h += turn * std::clamp((s - corner + 0.5) / 1.0, 0.0, 1.0);
        return h;
    }

private:
    double start_ = 0.0, last_ = 0.0;
    std::vector<std::pair<double, double>> turns_;
};

// One scan: AP a heard with mean RSS means[a] (the environment where and when it was heard).
Scan take_scan(const Environment& env, const std::vector<double>& means, double offset_db, std::mt19937_64& rng) {
    const Scenario& sc = env.scenario();
    std::normal_distribution<double> noise(0.0, sc.noise_sigma_db);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    Scan scan;
    for (std::size_t a = 0; a < sc.aps.size(); ++a) {
        const double rss = std::round(means[a] + offset_db + noise(rng));  // phones report whole dBm
        const bool missed = u01(rng) < sc.miss_probability;
        if (rss < sc.sensitivity_dbm || missed) continue;
        scan.push_back({"wifi", sc.aps[a].bssid, std::clamp(rss, kMinRss, kMaxRss)});
    }
    return scan;
}

std::vector<double> means_at(const Environment& env, Point p) {
    std::vector<double> m;
    for (std::size_t a = 0; a < env.scenario().aps.size(); ++a) m.push_back(env.mean_rss(a, p));
    return m;
}

}  // namespace

SimConfig default_config(const std::string& scenario) {
    SimConfig c;
    if (scenario == "open_area" || scenario == kOpenAreaAlias) {
        c.heading_walk_rad_per_sqrt_m = 0.04;
        c.misalignment_sigma_rad = 0.04;
        c.step_length_person_sigma = 0.05;
        c.beacon_noise_sigma_db = 3.75;
    }
    return c;
}

Walk simulate(const Scenario& sc, std::uint64_t seed, const SimConfig& cfg) {
    const Environment env(sc);
    std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                      static_cast<std::uint32_t>(sc.environment_seed)};
    std::mt19937_64 rng(seq);
    std::normal_distribution<double> n01(0.0, 1.0);

    Walk walk;
    walk.scenario = sc.name;
    walk.seed = seed;
    walk.rate_hz = cfg.rate_hz;
    walk.start = sc.path.front();
    walk.north_offset_deg = sc.north_offset_deg;
    walk.map = sc.map;
    walk.earth_field_ut = std::hypot(sc.earth_horizontal_ut, sc.earth_vertical_ut);
    const HeadingProfile heading(sc.path);
    walk.start_heading_rad = heading.at(0.0);

    // The person and the phone of this walk.
    // Person draws are truncated at ±2σ: a 3σ gait would be a shuffle or a stomp.
    auto draw2 = [&] { return std::clamp(n01(rng), -2.0, 2.0); };
    const double mean_length = cfg.step_length_m * (1.0 + cfg.step_length_person_sigma * draw2());
    const double frequency = cfg.step_frequency_hz * (1.0 + 0.04 * draw2());
    const double bounce = cfg.bounce_p2p * std::exp(cfg.bounce_log_sigma * draw2());
    const Eigen::Vector3d acc_bias = cfg.acc_bias_sigma * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    const Eigen::Vector3d gyro_bias = cfg.gyro_bias_sigma * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    const double device_offset = cfg.device_offset_sigma_db * n01(rng);
    const double misalignment = cfg.misalignment_sigma_rad * n01(rng);

    // Steps: each a full cycle of vertical bounce; a longer step bounces more, with the
    // fourth power of Weinberg's relation.
    const double total = sc.path_length_m();
    std::vector<PlannedStep> steps;
    double t = cfg.stand_before_s, s = 0.0;
    while (s < total - 1e-9) {
        const double length = std::min(total - s, mean_length * (1.0 + cfg.step_length_sigma * n01(rng)));
        const double duration = (1.0 / frequency) * (1.0 + 0.03 * n01(rng));
        const double amplitude = 0.5 * bounce * std::pow(length / mean_length, 4.0);
        steps.push_back({t, duration, s, length, amplitude});
        t += duration;
        s += length;
    }
    const double t_end = t + cfg.stand_after_s;

    // The compass's wandering rotation at each step's start (and the walk's end), from its own
    // stream so that every other draw of the walk is the same with it on or off.
    std::seed_seq heading_seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                              static_cast<std::uint32_t>(sc.environment_seed), 0x48454144u};
    std::mt19937_64 heading_rng(heading_seq);
    std::vector<double> wander{0.0};
    for (const PlannedStep& st : steps)
        wander.push_back(wander.back() + cfg.heading_walk_rad_per_sqrt_m * std::sqrt(st.length) * n01(heading_rng));

    // Kinematics on the sample grid first, so rates come from differences of the angles.
    const double dt = 1.0 / cfg.rate_hz;
    const std::size_t n = static_cast<std::size_t>(std::floor(t_end * cfg.rate_hz)) + 1;
    std::vector<double> arc(n), yaw(n), walk_dir(n), pitch(n), roll(n), vert(n), fwd(n), lat(n);
    std::size_t cur = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const double tk = static_cast<double>(k) * dt;
        while (cur < steps.size() && tk >= steps[cur].t0 + steps[cur].duration) ++cur;
        const bool walking = cur < steps.size() && tk >= steps[cur].t0;
        double sk = cur < steps.size() ? steps[cur].s0 : total;
        double bias = wander[cur];
        if (walking) {
            const PlannedStep& st = steps[cur];
            const double u = (tk - st.t0) / st.duration;
            sk = st.s0 + st.length * u;
            bias += u * (wander[cur + 1] - wander[cur]);
            vert[k] = st.amplitude * (std::sin(2.0 * kPi * u) + 0.1 * std::sin(4.0 * kPi * u + 0.6));
            fwd[k] = 0.5 * st.amplitude * std::cos(2.0 * kPi * u);
            lat[k] = 0.3 * st.amplitude * std::sin(kPi * (static_cast<double>(cur) + u));
            pitch[k] = 0.1 + 0.02 * std::sin(2.0 * kPi * frequency * tk);
            roll[k] = 0.02 * std::sin(kPi * frequency * tk);
        } else {
            pitch[k] = 0.1;  // held tilted ~6° towards the user
        }
        arc[k] = sk;
        yaw[k] = heading.at(sk) + misalignment + bias;
        walk_dir[k] = heading.at(sk);
    }

    walk.imu.reserve(n);
    std::normal_distribution<double> acc_noise(0.0, cfg.acc_noise), gyro_noise(0.0, cfg.gyro_noise),
        mag_noise(0.0, cfg.mag_noise);
    for (std::size_t k = 0; k < n; ++k) {
        const double tk = static_cast<double>(k) * dt;
        const std::size_t kp = k > 0 ? k - 1 : k, kn = k + 1 < n ? k + 1 : k;
        const double span = static_cast<double>(kn - kp) * dt;
        const double yaw_rate = pdr::wrap_angle(yaw[kn] - yaw[kp]) / span;
        const double pitch_rate = (pitch[kn] - pitch[kp]) / span, roll_rate = (roll[kn] - roll[kp]) / span;

        // Device attitude: yaw ψ clockwise about up (a rotation of −ψ), then pitch about the
        // device x axis, then roll about its y axis.
        const Eigen::Matrix3d rz = Eigen::AngleAxisd(-yaw[k], Eigen::Vector3d::UnitZ()).toRotationMatrix();
        const Eigen::Matrix3d rx = Eigen::AngleAxisd(pitch[k], Eigen::Vector3d::UnitX()).toRotationMatrix();
        const Eigen::Matrix3d ry = Eigen::AngleAxisd(roll[k], Eigen::Vector3d::UnitY()).toRotationMatrix();
        const Eigen::Matrix3d r_wd = rz * rx * ry;

        const double walking = walk_dir[k];
        const Eigen::Vector3d forward(std::sin(walking), std::cos(walking), 0.0);
        const Eigen::Vector3d right(std::cos(walking), -std::sin(walking), 0.0);
        const Eigen::Vector3d specific_force = fwd[k] * forward + lat[k] * right + Eigen::Vector3d(0, 0, kG + vert[k]);
        const Eigen::Vector3d omega = ry.transpose() * rx.transpose() * Eigen::Vector3d(0, 0, -yaw_rate) +
                                      ry.transpose() * Eigen::Vector3d(pitch_rate, 0, 0) +
                                      Eigen::Vector3d(0, roll_rate, 0);
        const Point truth = point_at_arc(sc.path, arc[k]);

        ImuSample smp;
        smp.t_s = tk;
        smp.acc = to_vec3(r_wd.transpose() * specific_force + acc_bias +
                          Eigen::Vector3d(acc_noise(rng), acc_noise(rng), acc_noise(rng)));
        smp.gyro = to_vec3(omega + gyro_bias + Eigen::Vector3d(gyro_noise(rng), gyro_noise(rng), gyro_noise(rng)));
        smp.mag = to_vec3(r_wd.transpose() * env.magnetic_field(truth) +
                          Eigen::Vector3d(mag_noise(rng), mag_noise(rng), mag_noise(rng)));
        smp.truth = truth;
        walk.imu.push_back(smp);
    }

    // The radio draws of the walk beyond the original model come from their own stream, so
    // turning them on or off leaves the person, the IMU and every other draw unchanged.
    std::seed_seq radio_seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                            static_cast<std::uint32_t>(sc.environment_seed), 0x52414449u};
    std::mt19937_64 radio_rng(radio_seq);
    std::vector<SmoothField> drift;
    for (std::size_t a = 0; a < sc.aps.size(); ++a)
        drift.emplace_back(radio_rng, cfg.survey_drift_sigma_db, cfg.survey_drift_scale_m);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    auto truth_at_time = [&](double tq) {
        const std::size_t k = std::min(n - 1, static_cast<std::size_t>(std::lround(std::max(0.0, tq) * cfg.rate_hz)));
        return *walk.imu[k].truth;
    };

    for (double ts = 0.5 * cfg.scan_period_s; ts < t_end; ts += cfg.scan_period_s) {
        const std::size_t k = std::min(n - 1, static_cast<std::size_t>(std::lround(ts * cfg.rate_hz)));
        const Point at = *walk.imu[k].truth;
        std::vector<double> means(sc.aps.size());
        for (std::size_t a = 0; a < sc.aps.size(); ++a) {
            const double heard = walk.imu[k].t_s - cfg.scan_duration_s * u01(radio_rng);
            const Point p = cfg.scan_duration_s > 0.0 ? truth_at_time(heard) : at;
            means[a] = env.mean_rss(a, p) + drift[a](p);
        }
        walk.scans.push_back({walk.imu[k].t_s, take_scan(env, means, device_offset, rng), at});
    }

    // Anchor readings from a stream of their own: a scenario without anchors draws nothing here.
    if (!sc.beacons.empty() && cfg.beacon_rate_hz > 0.0) {
        std::seed_seq beacon_seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                                 static_cast<std::uint32_t>(sc.environment_seed), 0x424c4521u};
        std::mt19937_64 beacon_rng(beacon_seq);
        std::normal_distribution<double> b01(0.0, 1.0);
        const double phone_offset = cfg.beacon_phone_offset_sigma_db * b01(beacon_rng);
        for (const Beacon& b : sc.beacons)
            walk.anchors.push_back({b.type, b.id, {b.at, b.height_m - sc.phone_height_m, {b.tx_power_dbm, b.exponent}}});
        for (double ts = 0.5 / cfg.beacon_rate_hz; ts < t_end; ts += 1.0 / cfg.beacon_rate_hz) {
            const Point at = truth_at_time(ts);
            Scan scan;
            for (std::size_t b = 0; b < sc.beacons.size(); ++b) {
                const double rss =
                    std::round(env.beacon_mean_rss(b, at) + phone_offset + cfg.beacon_noise_sigma_db * b01(beacon_rng));
                if (rss < sc.beacon_sensitivity_dbm) continue;
                scan.push_back({sc.beacons[b].type, sc.beacons[b].id, std::clamp(rss, kMinRss, kMaxRss)});
            }
            walk.anchor_scans.push_back({ts, std::move(scan), at});
        }
    }

    for (std::size_t i = 0; i < sc.rps.size(); ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "rp%02zu", i + 1);
        SurveyPoint rp{name, sc.rps[i], {}};
        const std::vector<double> means = means_at(env, rp.at);
        for (int j = 0; j < cfg.survey_scans; ++j) rp.scans.push_back(take_scan(env, means, 0.0, rng));
        walk.survey.push_back(std::move(rp));
    }
    return walk;
}

}  // namespace locus::sim
