// A thin client's POST /v1/tracks/{id}/steps as the server fuses it (tracks::ThinFusion, no
// HTTP): the copy of the track's filter a request runs on, then a typical batch (4 steps and
// the radio fix of one ~4 s WiFi scan), with walk_pf (the default) and the particle filter, on
// the PUTMC floor's plan made from its drawing; walk_pf also without a plan. Counters: the
// bytes one live track's filter holds (track_bytes) and those of the floor's shared plan
// structures (floor_bytes: PlanWalkable, built once per plan version). Skipped when the
// shared data folder is absent. And a Kalman track's request (kalman_trilateration, kalman_ranging,
// ekf_ranging): its scan of six transmitters ranged (trilateration, multilateration) and fused
// with 4 steps (ekf_ranging: the scan's six readings are its measurements).
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "image_file.hpp"
#include "locus/imaging/plan_from_image.hpp"
#include "locus/ranging/trilateration.hpp"
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
    // What one live track holds, and (on the plan) what the floor's tracks share.
    state.counters["track_bytes"] = static_cast<double>(track->memory_bytes());
    if (plan) state.counters["floor_bytes"] = static_cast<double>(plan->floor_plan->memory_bytes());
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

// A Kalman track's request as POST /v1/tracks/{id}/steps runs it past the HTTP layer and the
// transmitter cache (transmitter_cache_bench): the scan ranged on six transmitters around a 14 m ×
// 12 m room (the Kalman-fusion paper's trilateration or multilateration), then the filter's copy
// runs 4 steps and the ranged fix. Arg 0: 0 = kalman_trilateration, 1 = kalman_ranging, 2 =
// ekf_ranging (the scan multilaterated as the route does, its six readings the update).
void BM_ThinFusionRangingRequest(benchmark::State& state) {
    const bool ekf = state.range(0) == 2;
    const bool ours = state.range(0) >= 1;
    const std::vector<ranging::Transmitter> txs = {{{1, 1}, 1.3, {-40, 2.0}},  {{14, 1}, 1.3, {-42, 2.1}}, {{14, 13}, 1.3, {-41, 2.0}},
                                                   {{1, 13}, 1.3, {-39, 1.9}}, {{7, 7}, 1.6, {-40, 2.0}},  {{11, 7}, 1.0, {-41, 2.0}}};
    const auto method = ekf ? tracks::FusionMethod::ekf_ranging : ours ? tracks::FusionMethod::kalman_ranging : tracks::FusionMethod::kalman_trilateration;
    auto anchors = std::make_shared<tracks::FloorAnchors>();
    for (std::size_t i = 0; i < txs.size(); ++i) anchors->by_floor[1].push_back({"wifi|tx" + std::to_string(i), txs[i]});
    const auto no_plan = [](std::int64_t) { return std::shared_ptr<const fusion::Walkable>(); };
    const auto scan_at = [&](double t, Point p, int k) {
        std::vector<ranging::Heard> heard;
        std::vector<fusion::AnchorReading> readings;
        for (std::size_t i = 0; i < txs.size(); ++i) {
            const double d = std::hypot(distance(txs[i].at, p), txs[i].dz);
            heard.push_back({txs[i], ranging::rss_at(txs[i].model, d) + 2.0 * std::sin(1.7 * k + 2.3 * static_cast<double>(i))});
            if (ekf) readings.push_back({"wifi|tx" + std::to_string(i), t, heard.back().rss});
        }
        const auto f = ours ? ranging::multilaterate(heard) : ranging::trilaterate(heard);
        tracks::RadioFix r;
        r.t = t;
        r.floor_id = 1;
        r.x = f ? f->at.x : p.x;
        r.y = f ? f->at.y : p.y;
        r.accuracy_m = 1.0;
        if (f) r.ranged = *f;
        r.readings = std::move(readings);
        return r;
    };
    auto track = std::make_shared<tracks::ThinFusion>(method, 7);
    track->set_anchors(anchors);
    track->run({}, {scan_at(0, {3, 3}, 0)}, no_plan);
    double t = 0;
    Point at{3, 3};
    int k = 0;
    for (auto _ : state) {
        // Laps of the room's middle: 8 steps east, 8 west.
        const bool east = (k / 2) % 2 == 0;
        std::vector<tracks::Step> steps;
        for (int i = 1; i <= 4; ++i) steps.push_back({t + i, 0.7, east ? 90.0 : 270.0});
        at.x += east ? 2.8 : -2.8;
        auto next = std::make_shared<tracks::ThinFusion>(*track);
        benchmark::DoNotOptimize(next->run(steps, {scan_at(t + 4, at, ++k)}, no_plan));
        track = std::move(next);
        t += 4;
    }
}
BENCHMARK(BM_ThinFusionRangingRequest)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
