// Step-detector throughput (docs/pdr.md target: ≥ 1 M accelerometer samples/s per core).
// Synthetic 100 Hz walk with noise, pre-generated so only the detector is timed; a second
// benchmark replays a real Oxford trace when the data set is present.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "locus/motion/pdr/step_detector.hpp"
#include "build_paths.hpp"

namespace {

struct Sample {
    double t, x, y, z;
};

std::vector<Sample> synthetic(std::size_t n, double rate) {
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 0.3);
    std::vector<Sample> v(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double t = static_cast<double>(i) / rate;
        const double av = 2.0 * std::sin(2.0 * std::numbers::pi * 1.8 * t);
        v[i] = {t, 0.3 * av + noise(rng), 0.5 * av + noise(rng), 9.81 + 0.8 * av + noise(rng)};
    }
    return v;
}

void run(benchmark::State& state, const std::vector<Sample>& v) {
    std::uint64_t steps = 0;
    for (auto _ : state) {
        locus::pdr::StepDetector d;
        for (const auto& s : v) benchmark::DoNotOptimize(d.push(s.t, s.x, s.y, s.z));
        steps = d.steps();
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(v.size()));
    state.counters["steps"] = static_cast<double>(steps);
}

void BM_StepDetectorSynthetic(benchmark::State& state) {
    static const auto v = synthetic(1'000'000, static_cast<double>(state.range(0)));
    run(state, v);
}
BENCHMARK(BM_StepDetectorSynthetic)->Arg(100)->Unit(benchmark::kMillisecond);

void BM_StepDetectorOxfordTrace(benchmark::State& state) {
    static std::vector<Sample> v = [] {
        std::vector<Sample> out;
        std::ifstream in(std::string(LOCUS_DATA_DIR) +
                         "/oxford-step-counter/optimisation/data/Pixel_Jamie_Hard_InHand_1/accelerometer.csv");
        std::string line;
        while (std::getline(in, line)) {
            long long ns;
            int acc;
            double x, y, z;
            if (std::sscanf(line.c_str(), "%lld,%d,%lf,%lf,%lf", &ns, &acc, &x, &y, &z) == 5)
                out.push_back({static_cast<double>(ns) * 1e-9, x, y, z});
        }
        return out;
    }();
    if (v.empty()) {
        state.SkipWithError("Oxford data set not found under LOCUS_DATA_DIR");
        return;
    }
    run(state, v);
}
BENCHMARK(BM_StepDetectorOxfordTrace)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
