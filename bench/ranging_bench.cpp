// Positioning from transmitters at known positions (the budgets docs/transmitters.md sets):
// multilateration and the Kalman-fusion paper's trilateration with 20 transmitters heard (≤ 50 µs
// per query), the model fit of one AP from a survey, and a modelled radio map of 10,000 grid RPs
// from 200 transmitters and 2,000 walls (≤ 5 s).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "locus/ranging/fit.hpp"
#include "locus/ranging/propagation.hpp"
#include "locus/ranging/trilateration.hpp"

using namespace locus;
using namespace locus::ranging;

namespace {

// 20 transmitters scattered over a 40 m × 25 m floor and one query with 3 dB shadowing.
std::vector<Heard> twenty_heard(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> x(0, 40), y(0, 25);
    std::normal_distribution<double> noise(0, 3);
    const Point phone{x(rng), y(rng)};
    std::vector<Heard> out;
    for (int i = 0; i < 20; ++i) {
        Transmitter t{{x(rng), y(rng)}, 1.5, {-40.0, 2.2}};
        const double d = std::hypot(std::hypot(phone.x - t.at.x, phone.y - t.at.y), t.dz);
        out.push_back({t, rss_at(t.model, d) + noise(rng)});
    }
    return out;
}

void BM_Multilateration20(benchmark::State& state) {
    std::vector<std::vector<Heard>> queries;
    for (unsigned s = 1; s <= 64; ++s) queries.push_back(twenty_heard(s));
    std::size_t i = 0;
    for (auto _ : state) {
        auto fix = multilaterate(queries[i++ % queries.size()]);
        benchmark::DoNotOptimize(fix);
    }
}
BENCHMARK(BM_Multilateration20)->Unit(benchmark::kMicrosecond);

void BM_Trilateration20(benchmark::State& state) {
    std::vector<std::vector<Heard>> queries;
    for (unsigned s = 1; s <= 64; ++s) queries.push_back(twenty_heard(s));
    TrilaterationOptions o;
    o.cutoff = 1000;  // every transmitter kept: the 12 strongest, 220 triples
    std::size_t i = 0;
    for (auto _ : state) {
        auto fix = trilaterate(queries[i++ % queries.size()], o);
        benchmark::DoNotOptimize(fix);
    }
}
BENCHMARK(BM_Trilateration20)->Unit(benchmark::kMicrosecond);

void BM_FitPositionAndModel(benchmark::State& state) {
    // One AP heard at 300 RPs of a 40 m × 25 m survey.
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0, 3);
    std::uniform_real_distribution<double> x(0, 40), y(0, 25);
    const Transmitter t{{17.0, 9.0}, 0.0, {-41.0, 2.4}};
    std::vector<Sample> samples;
    for (int i = 0; i < 300; ++i) {
        const Point p{x(rng), y(rng)};
        samples.push_back({p, rss_at(t.model, std::hypot(p.x - t.at.x, p.y - t.at.y)) + noise(rng)});
    }
    FitOptions o;
    o.area = {0, 0, 40, 25};
    for (auto _ : state) {
        auto fit = fit_position_and_model(samples, o);
        benchmark::DoNotOptimize(fit);
    }
}
BENCHMARK(BM_FitPositionAndModel)->Unit(benchmark::kMillisecond);

// 10,000 grid RPs (100 m × 100 m at 1 m) from 200 transmitters and 2,000 walls (3 m each, in
// both directions), every transmitter modelling walls.
void BM_GenerateRadioMap10k(benchmark::State& state) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0, 100);
    std::vector<Segment> walls;
    for (int i = 0; i < 2000; ++i) {
        const Point a{u(rng), u(rng)};
        walls.push_back(i % 2 ? Segment{a, {a.x + 3, a.y}} : Segment{a, {a.x, a.y + 3}});
    }
    std::vector<ModelledTransmitter> txs;
    for (int i = 0; i < 200; ++i) txs.push_back({{{u(rng), u(rng)}, 1.5, {-40.0, 2.0}}, 3.0});
    const auto points = grid_points({0, 0, 100, 100}, 1.0);
    std::size_t readings = 0;
    for (auto _ : state) {
        const WallIndex index(walls);
        readings = 0;
        for (const Point p : points) readings += modelled_rss(p, txs, index, -95.0).size();
        benchmark::DoNotOptimize(readings);
    }
    state.counters["rps"] = static_cast<double>(points.size());
    state.counters["readings_per_rp"] = static_cast<double>(readings) / static_cast<double>(points.size());
}
BENCHMARK(BM_GenerateRadioMap10k)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
