// Relative positioning (Bonjorn López 2016, docs/spec.md §8) on the phone: what one acoustic
// exchange costs a phone (finding both chirps in a 0.2 s recording with the direct-form matched
// filter) and one estimator step.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "locus/motion/relative/acoustic.hpp"
#include "locus/motion/relative/direction_estimator.hpp"
#include "locus/motion/relative/range_fit.hpp"
#include "locus/motion/relative/range_kalman.hpp"

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

// One step of the distance filter: a prediction and an RSSI update.
static void BM_RangeKalmanStep(benchmark::State& state) {
    locus::relative::RangeKalman f;
    f.update_rssi(20.0);
    double d = 20.0;
    for (auto _ : state) {
        f.predict(0.7);
        d = d > 2.0 ? d - 0.7 : 20.0;
        f.update_rssi(d);
        benchmark::DoNotOptimize(f.distance());
    }
}
BENCHMARK(BM_RangeKalmanStep);

// The range fit over N (position, distance) pairs: what rssi-fit runs at every step (N grows
// to 60 in a 30 s walk).
static void BM_RangeFit(benchmark::State& state) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> noise(0.0, 0.37);
    std::vector<locus::Point> at;
    std::vector<double> d;
    for (int k = 0; k < state.range(0); ++k) {
        at.push_back({0.7 * k, 0.1 * k});
        d.push_back(std::hypot(15.0 - at.back().x, 8.0 - at.back().y) * std::exp(noise(rng)));
    }
    for (auto _ : state) benchmark::DoNotOptimize(locus::relative::fit_target(at, d, at.back(), d.back(), 30.0));
}
BENCHMARK(BM_RangeFit)->Arg(10)->Arg(60)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
