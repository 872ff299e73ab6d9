#include "locus/motion/relative/acoustic.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace locus::relative {

double chirp_at(const ChirpParams& p, double t) {
    const double duration = double(p.samples) / p.sample_rate;
    if (t < 0.0 || t >= duration) return 0.0;
    const double rate = (p.f1 - p.f0) / duration;
    return std::sin(2.0 * std::numbers::pi * (p.f0 * t + 0.5 * rate * t * t));
}

std::vector<double> chirp(const ChirpParams& p) {
    std::vector<double> s(p.samples);
    for (std::size_t k = 0; k < p.samples; ++k) s[k] = chirp_at(p, double(k) / p.sample_rate);
    return s;
}

std::vector<std::int16_t> chirp_pcm(const ChirpParams& p, double amplitude) {
    amplitude = std::clamp(amplitude, 0.0, 32767.0);
    std::vector<std::int16_t> out;
    out.reserve(p.samples);
    for (double v : chirp(p)) out.push_back(static_cast<std::int16_t>(std::lround(v * amplitude)));
    return out;
}

std::vector<double> matched_filter(std::span<const double> x, std::span<const double> s) {
    if (s.empty() || x.size() < s.size()) return {};
    std::vector<double> y(x.size() - s.size() + 1);
    for (std::size_t n = 0; n < y.size(); ++n) {
        double acc = 0.0;
        for (std::size_t k = 0; k < s.size(); ++k) acc += x[n + k] * s[k];
        y[n] = acc;
    }
    return y;
}

std::vector<Detection> detect_chirps(std::span<const double> recording, const ChirpParams& p, std::size_t count) {
    const auto templ = chirp(p);
    std::vector<double> y = matched_filter(recording, templ);
    for (double& v : y) v = std::abs(v);
    std::vector<Detection> found;
    while (found.size() < count) {
        auto best = std::max_element(y.begin(), y.end());
        if (best == y.end() || *best <= 0.0) break;
        const auto at = std::size_t(best - y.begin());
        found.push_back({at, *best});
        // A chirp's correlation side lobes reach one chirp length either way.
        const std::size_t lo = at >= p.samples ? at - p.samples : 0;
        const std::size_t hi = std::min(y.size(), at + p.samples);
        std::fill(y.begin() + std::ptrdiff_t(lo), y.begin() + std::ptrdiff_t(hi), 0.0);
    }
    std::sort(found.begin(), found.end(), [](const Detection& a, const Detection& b) { return a.sample < b.sample; });
    return found;
}

std::vector<Detection> detect_chirps(std::span<const std::int16_t> recording, const ChirpParams& p,
                                     std::size_t count) {
    std::vector<double> x(recording.begin(), recording.end());
    return detect_chirps(std::span<const double>(x), p, count);
}

bool own_and_remote(std::span<const double> recording, const ChirpParams& p, TwoWayCounts& out) {
    const auto d = detect_chirps(recording, p, 2);
    if (d.size() < 2) return false;
    const bool first_is_own = d[0].strength >= d[1].strength;
    out.own = double(first_is_own ? d[0].sample : d[1].sample);
    out.remote = double(first_is_own ? d[1].sample : d[0].sample);
    return true;
}

double two_way_distance(const TwoWayCounts& a, const TwoWayCounts& b, double sample_rate, double speed_of_sound,
                        double self_a, double self_b) {
    const double samples = (a.remote - a.own) + (b.remote - b.own);
    return speed_of_sound / 2.0 * samples / sample_rate + (self_a + self_b) / 2.0;
}

}  // namespace locus::relative
