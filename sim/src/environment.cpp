#include "sim/environment.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace locus::sim {

SmoothField::SmoothField(std::mt19937_64& rng, double sigma, double scale_m, int components) {
    std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
    std::uniform_real_distribution<double> stretch(0.7, 1.5);
    for (int i = 0; i < components; ++i) {
        const double k = 2.0 * std::numbers::pi / (scale_m * stretch(rng));
        const double dir = angle(rng);
        waves_.push_back({k * std::cos(dir), k * std::sin(dir), angle(rng)});
    }
    // Each cosine with a uniform phase has variance ½.
    amplitude_ = components > 0 ? sigma * std::sqrt(2.0 / components) : 0.0;
}

double SmoothField::operator()(Point p) const {
    double v = 0.0;
    for (const Wave& w : waves_) v += std::cos(w.kx * p.x + w.ky * p.y + w.phase);
    return amplitude_ * v;
}

Environment::Environment(const Scenario& scenario) : scenario_(scenario) {
    std::mt19937_64 rng(scenario.environment_seed);
    for (std::size_t i = 0; i < scenario.aps.size(); ++i)
        shadowing_.emplace_back(rng, scenario.shadowing_sigma_db, scenario.shadowing_scale_m);
    deflection_ = SmoothField(rng, scenario.structure_deflection_rad, scenario.structure_scale_m);
    ripple_ = SmoothField(rng, scenario.structure_norm_ripple, scenario.structure_scale_m);
    // Drawn last, so the other fields of a scenario without anchors are as they were.
    for (std::size_t i = 0; i < scenario.beacons.size(); ++i)
        beacon_shadowing_.emplace_back(rng, scenario.beacon_shadowing_sigma_db, scenario.beacon_shadowing_scale_m);
}

double Environment::beacon_mean_rss(std::size_t b, Point p) const {
    const Beacon& a = scenario_.beacons[b];
    const double dz = a.height_m - scenario_.phone_height_m;
    const double d = std::max(1.0, std::hypot(distance(a.at, p), dz));
    return a.tx_power_dbm - 10.0 * a.true_exponent * std::log10(d) + beacon_shadowing_[b](p);
}

int Environment::walls_between(Point a, Point b) const {
    const auto& plan = scenario_.map.plan;
    const double len = distance(a, b);
    const int n = std::max(1, static_cast<int>(std::ceil(len / 0.2)));
    const Room* last = plan.room_at(a);
    int walls = 0;
    for (int i = 1; i <= n; ++i) {
        const double t = static_cast<double>(i) / n;
        const Room* r = plan.room_at({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
        if (r != last) ++walls;
        last = r;
    }
    return walls;
}

double Environment::mean_rss(std::size_t ap, Point p) const {
    const AccessPoint& a = scenario_.aps[ap];
    const double d = std::max(1.0, distance(a.at, p));
    return a.rss_1m_dbm - 10.0 * scenario_.path_loss_exponent * std::log10(d) -
           scenario_.wall_loss_db * walls_between(a.at, p) + shadowing_[ap](p);
}

Eigen::Vector3d Environment::magnetic_field(Point p) const {
    // Earth's field points to magnetic north; local north is north_offset clockwise from it,
    // so in the floor frame magnetic north lies at azimuth −north_offset.
    const double north = -scenario_.north_offset_deg * std::numbers::pi / 180.0 + deflection_(p);
    const double h = scenario_.earth_horizontal_ut * (1.0 + ripple_(p));
    Eigen::Vector3d b(h * std::sin(north), h * std::cos(north), scenario_.earth_vertical_ut * (1.0 + ripple_(p)));
    for (const MagneticSource& s : scenario_.sources) {
        const double dx = p.x - s.at.x, dy = p.y - s.at.y;
        const double r = std::hypot(dx, dy);
        const double fade = s.strength_ut * std::exp(-0.5 * r * r / (s.radius_m * s.radius_m));
        if (r > 1e-9) b += Eigen::Vector3d(fade * dx / r, fade * dy / r, -0.5 * fade);
        else b.z() -= 0.5 * fade;
    }
    return b;
}

}  // namespace locus::sim
