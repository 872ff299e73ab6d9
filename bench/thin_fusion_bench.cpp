// A thin client's POST /v1/tracks/{id}/steps as the server fuses it (tracks::ThinFusion, no
// HTTP): the copy of the track's filter a request runs on, then a typical batch (4 steps and
// the radio fix of one ~4 s WiFi scan), with walk_pf (the default) and the particle filter, on
// the PUTMC floor's plan made from its drawing; walk_pf also without a plan. Skipped when the
// shared data folder is absent.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <optional>

#include "image_file.hpp"
#include "locus/imaging/plan_from_image.hpp"
#include "tracks/fusion.hpp"

using namespace locus;

namespace {

const std::string kImage = LOCUS_DATA_DIR "/putmc/map/floorplan.png";
constexpr double kPxPerM = 28.3988631094;

std::shared_ptr<const fusion::Walkable> putmc_floor() {
    static const std::shared_ptr<const fusion::Walkable> floor = []() -> std::shared_ptr<const fusion::Walkable> {
        if (!std::filesystem::exists(kImage)) return nullptr;
        imaging::FromImageOptions o;
        o.px_per_m = kPxPerM;
        return std::make_shared<const fusion::Walkable>(fusion::Walkable::from_plan(imaging::plan_from_image(tools::read_grey_image(kImage), o)));
    }();
    return floor;
}

// A corridor point of the PUTMC floor (walk 1's first truth point, y flipped).
constexpr Point kStart{59.58, 36.94 - 23.27};

tracks::RadioFix radio(double t, double x) {
    tracks::RadioFix f;
    f.t = t;
    f.floor_id = 1;
    f.x = x;
    f.y = kStart.y;
    f.accuracy_m = 2.0;
    return f;
}

// Arg 0: 0 = walk_pf, 1 = particle; arg 1: 1 = on the plan, 0 = no plan.
void BM_ThinFusionRequest(benchmark::State& state) {
    const auto method = state.range(0) ? tracks::FusionMethod::particle : tracks::FusionMethod::walk_pf;
    std::shared_ptr<const fusion::Walkable> plan;
    if (state.range(1)) {
        plan = putmc_floor();
        if (!plan) return state.SkipWithError("no PUTMC data");
    }
    const auto walkable_of = [&plan](std::int64_t) { return plan; };
    auto track = std::make_shared<tracks::ThinFusion>(method, 7);
    track->run({}, {radio(0, kStart.x)}, walkable_of);
    double t = 0, x = kStart.x;
    for (auto _ : state) {
        // 14 m west along the corridor and back (as walk_filter_bench), a fix after every 4 steps.
        const bool west = static_cast<int>(t / 20) % 2 == 0;
        std::vector<tracks::Step> steps;
        for (int i = 1; i <= 4; ++i) steps.push_back({t + i, 0.7, west ? 270.0 : 90.0});
        x += west ? -2.8 : 2.8;
        // The request runs on a copy, kept once its fixes are stored (tracks::Service::post_raw).
        auto next = std::make_shared<tracks::ThinFusion>(*track);
        benchmark::DoNotOptimize(next->run(steps, {radio(t + 4, x)}, walkable_of));
        track = std::move(next);
        t += 4;
    }
}
BENCHMARK(BM_ThinFusionRequest)->Args({0, 1})->Args({1, 1})->Args({0, 0})->Unit(benchmark::kMicrosecond);

// The copy alone: each filter holds its own Walkable (client-lib's filters own their map).
void BM_ThinFusionCopy(benchmark::State& state) {
    const auto method = state.range(0) ? tracks::FusionMethod::particle : tracks::FusionMethod::walk_pf;
    const auto plan = putmc_floor();
    if (!plan) return state.SkipWithError("no PUTMC data");
    tracks::ThinFusion track(method, 7);
    track.run({}, {radio(0, kStart.x)}, [&plan](std::int64_t) { return plan; });
    for (auto _ : state) benchmark::DoNotOptimize(std::make_shared<tracks::ThinFusion>(track));
}
BENCHMARK(BM_ThinFusionCopy)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
