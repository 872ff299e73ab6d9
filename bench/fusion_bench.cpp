// Cost of one fusion step on a phone-class CPU: a rule, a Kalman predict+update, and a
// particle-filter step and fix on the basement-sized plan, as rooms and doors and as the
// equivalent floor plan (map matching on a server's plan); run by hand, never by ctest.
#include <benchmark/benchmark.h>

#include <numbers>

#include "locus/motion/fusion/kalman.hpp"
#include "locus/motion/fusion/particle_filter.hpp"
#include "locus/motion/fusion/rooms_plan.hpp"
#include "locus/motion/fusion/rules.hpp"

using namespace locus;
using namespace locus::fusion;

namespace {

Walkable corridor_and_rooms() {
    Walkable w;
    w.plan.rooms.push_back({1, "corridor", {{0.0, 6.0, 36.0, 8.5}}});
    for (int i = 0; i < 4; ++i) {
        const double x0 = 9.0 * i;
        w.plan.rooms.push_back({2 + i, "room", {{x0, 0.0, x0 + 9.0, 6.0}}});
        w.doors.push_back({{x0 + 4.0, 6.0}, {x0 + 5.0, 6.0}});
    }
    return w;
}

// Arg 0: rooms and doors; 1: the same floor as a plan (Walkable::from_plan).
Walkable floor_of(std::int64_t as_plan) {
    return as_plan ? Walkable::from_plan(rooms_plan(corridor_and_rooms())) : corridor_and_rooms();
}

void BM_Rule(benchmark::State& state) {
    FusionInput in{{3.0, 0.0}, {0.0, 4.0}, Point{0.0, 0.0}, 5, std::nullopt};
    for (auto _ : state) benchmark::DoNotOptimize(fuse(Rule::proportional, in));
}
BENCHMARK(BM_Rule);

void BM_KalmanStepAndFix(benchmark::State& state) {
    KalmanFilter kf({1.0, 7.0});
    for (auto _ : state) {
        kf.predict({0.7, 0.0});
        kf.update({kf.position().x + 0.5, 7.0}, Eigen::Matrix2d::Identity());
    }
    benchmark::DoNotOptimize(kf.position());
}
BENCHMARK(BM_KalmanStepAndFix);

// Map-matched on the plan: arg 0 snaps each step into walkable space (the default), 1 blocks
// steps at walls. The walk bounces along the corridor and into its walls.
void BM_KalmanOnPlanStepAndFix(benchmark::State& state) {
    KalmanConfig c;
    c.walls_block_steps = state.range(0) != 0;
    KalmanFilter kf({1.0, 7.0}, c, floor_of(1).floor_plan);
    double dx = 0.7;
    for (auto _ : state) {
        kf.predict({dx, 0.3});
        kf.update({kf.position().x + 0.5, 7.0}, Eigen::Matrix2d::Identity());
        if (kf.position().x > 34.0 || kf.position().x < 2.0) dx = -dx;
    }
    benchmark::DoNotOptimize(kf.position());
}
BENCHMARK(BM_KalmanOnPlanStepAndFix)->Arg(0)->Arg(1);

void BM_ParticleStep(benchmark::State& state) {
    ParticleConfig c;
    c.particles = static_cast<int>(state.range(0));
    ParticleFilter pf(floor_of(state.range(1)), {1.0, 7.25}, c);
    double heading = std::numbers::pi / 2.0;
    for (auto _ : state) {
        pf.predict(0.7, heading);
        if (pf.position().x > 34.0 || pf.position().x < 2.0) heading = -heading;
    }
    benchmark::DoNotOptimize(pf.position());
}
BENCHMARK(BM_ParticleStep)->ArgsProduct({{250, 1000, 4000}, {0, 1}});

void BM_ParticleFix(benchmark::State& state) {
    ParticleConfig c;
    c.particles = static_cast<int>(state.range(0));
    ParticleFilter pf(floor_of(state.range(1)), {10.0, 7.25}, c);
    for (auto _ : state) pf.update({10.5, 7.0}, Eigen::Matrix2d::Identity() * 2.0);
    benchmark::DoNotOptimize(pf.position());
}
BENCHMARK(BM_ParticleFix)->ArgsProduct({{1000}, {0, 1}});

// Building the map matcher from a plan (its walk grid) when a floor's plan arrives.
void BM_PlanWalkableBuild(benchmark::State& state) {
    const auto plan = rooms_plan(corridor_and_rooms());
    for (auto _ : state) benchmark::DoNotOptimize(PlanWalkable(plan));
}
BENCHMARK(BM_PlanWalkableBuild);

}  // namespace
BENCHMARK_MAIN();
