// The tightly coupled ranging filter (fusion::RangingEkf, our answer to the Kalman-fusion paper,
// docs/spec.md §8): the cost of one PDR step (predict) and of one scan's update with the
// Kalman-fusion paper's six anchors and with 20 anchors heard, so a phone (1 Hz scans, ~2 steps/s)
// or a server running many tracks can budget it.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "locus/motion/fusion/ranging_ekf.hpp"

using namespace locus;
using namespace locus::fusion;

namespace {

std::vector<RangingAnchor> anchors(int count) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> x(0, 25), y(0, 12);
    std::vector<RangingAnchor> out;
    for (int i = 0; i < count; ++i) out.push_back({"anchor-" + std::to_string(i), {{x(rng), y(rng)}, 1.3, {-59.0, 2.0}}});
    return out;
}

// 64 scans from random points, 3.75 dB noise (the Kalman-fusion paper's).
std::vector<std::vector<AnchorReading>> scans(const std::vector<RangingAnchor>& as) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> x(2, 23), y(2, 10);
    std::normal_distribution<double> noise(0, 3.75);
    std::vector<std::vector<AnchorReading>> out;
    for (int s = 0; s < 64; ++s) {
        const Point p{x(rng), y(rng)};
        auto& scan = out.emplace_back();
        for (const RangingAnchor& a : as) {
            const double d = std::hypot(std::hypot(p.x - a.tx.at.x, p.y - a.tx.at.y), a.tx.dz);
            scan.push_back({a.id, static_cast<double>(s), -59.0 - 20.0 * std::log10(d) + noise(rng)});
        }
    }
    return out;
}

void BM_RangingEkfUpdate(benchmark::State& state) {
    const auto as = anchors(static_cast<int>(state.range(0)));
    const auto ss = scans(as);
    RangingEkf ekf({12.0, 6.0}, as);
    std::size_t i = 0;
    for (auto _ : state) {
        ekf.update(ss[i++ % ss.size()]);
        benchmark::DoNotOptimize(ekf.position());
    }
    state.counters["readings"] = static_cast<double>(as.size());
}
BENCHMARK(BM_RangingEkfUpdate)->Arg(6)->Arg(20);

void BM_RangingEkfPredict(benchmark::State& state) {
    const auto as = anchors(6);
    RangingEkf ekf({12.0, 6.0}, as);
    double t = 0.0;
    for (auto _ : state) {
        t += 0.5;
        ekf.predict({0.7 * std::cos(t), 0.7 * std::sin(t)}, t);
        benchmark::DoNotOptimize(ekf.position());
    }
}
BENCHMARK(BM_RangingEkfPredict);

}  // namespace

BENCHMARK_MAIN();
