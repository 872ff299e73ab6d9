// Seed 001 on the phone: what one acoustic exchange costs a phone (finding both chirps in a
// 0.2 s recording with the direct-form matched filter) and one estimator step.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "locus/relative/acoustic.hpp"
#include "locus/relative/direction_estimator.hpp"

using namespace locus::relative;

static void BM_DetectTwoChirps(benchmark::State& state) {
    ChirpParams p;
    const double seconds = double(state.range(0)) / 1000.0;
    std::vector<double> rec(std::size_t(seconds * p.sample_rate));
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 0.01);
    for (std::size_t i = 0; i < rec.size(); ++i)
        rec[i] = noise(rng) + chirp_at(p, double(i) / p.sample_rate - 0.03) + 0.1 * chirp_at(p, double(i) / p.sample_rate - 0.1);
    for (auto _ : state) benchmark::DoNotOptimize(detect_chirps(rec, p));
    state.SetLabel(std::to_string(rec.size()) + " samples");
}
BENCHMARK(BM_DetectTwoChirps)->Arg(200)->Arg(500)->Unit(benchmark::kMillisecond);

static void BM_EstimatorStep(benchmark::State& state) {
    DirectionEstimator e;
    double x = 0;
    e.step({0, 0}, 20.0);
    for (auto _ : state) {
        x += 0.7;
        if (x > 15) {
            e = DirectionEstimator{};
            e.step({0, 0}, 20.0);
            x = 0.7;
        }
        benchmark::DoNotOptimize(e.step({x, 0.1}, 20.0 - x));
        benchmark::DoNotOptimize(e.target());
    }
}
BENCHMARK(BM_EstimatorStep);

BENCHMARK_MAIN();
