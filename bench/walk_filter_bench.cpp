// The real-walk particle filter (fusion::WalkFilter) per PDR step and per fix, on the PUTMC
// floor's plan made from its drawing (as `locus import putmc` puts it), by particle count; and
// without a plan; and building the plan's map-matching structures. Skipped when the shared
// data folder is absent.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <optional>

#include "image_file.hpp"
#include "locus/motion/fusion/walk_filter.hpp"
#include "locus/imaging/plan_from_image.hpp"
#include "build_paths.hpp"

using namespace locus;

namespace {

const std::string kImage = std::string(LOCUS_DATA_DIR) + "/putmc/map/floorplan.png";
constexpr double kPxPerM = 28.3988631094;

// Built once: making the plan takes about a second.
const std::optional<fusion::Walkable>& putmc_floor() {
    static const std::optional<fusion::Walkable> floor = [] {
        if (!std::filesystem::exists(kImage)) return std::optional<fusion::Walkable>();
        imaging::FromImageOptions o;
        o.px_per_m = kPxPerM;
        return std::optional(fusion::Walkable::from_plan(imaging::plan_from_image(tools::read_grey_image(kImage), o)));
    }();
    return floor;
}

// A corridor point of the PUTMC floor (walk 1's first truth point, y flipped).
constexpr Point kStart{59.58, 36.94 - 23.27};

// Arg 0: particles; arg 1: 1 = on the plan, 0 = no plan.
void BM_WalkFilterStep(benchmark::State& state) {
    std::optional<fusion::Walkable> map;
    if (state.range(1)) {
        if (!putmc_floor()) return state.SkipWithError("no PUTMC data");
        map = putmc_floor();
    }
    fusion::WalkFilterConfig cfg;
    cfg.particles = static_cast<int>(state.range(0));
    fusion::WalkFilter pf(map, cfg);
    pf.fix(kStart, Eigen::Matrix2d::Identity() * 4.0);
    int n = 0;
    for (auto _ : state) {
        // Up and down the corridor, a fix every 6 steps to keep the cloud on it.
        pf.step(0.7, (n / 20) % 2 ? 1.6 : -1.5);
        if (++n % 6 == 0) {
            state.PauseTiming();
            pf.fix(pf.position(), Eigen::Matrix2d::Identity() * 4.0);
            state.ResumeTiming();
        }
    }
    state.counters["particles"] = static_cast<double>(state.range(0));
    state.counters["filter_bytes"] = static_cast<double>(pf.memory_bytes());
    if (map) state.counters["floor_bytes"] = static_cast<double>(map->floor_plan->memory_bytes());
}
BENCHMARK(BM_WalkFilterStep)->ArgsProduct({{500, 2000, 8000}, {0, 1}})->Unit(benchmark::kMicrosecond);

// Building the floor's map-matching structures from its plan (the walk grid, clearances, the
// per-cell barrier lists): once per plan version, shared by every track on the floor.
void BM_PlanWalkableBuild(benchmark::State& state) {
    if (!putmc_floor()) return state.SkipWithError("no PUTMC data");
    const locus::plan::Plan& plan = putmc_floor()->floor_plan->plan();
    std::size_t bytes = 0;
    for (auto _ : state) {
        const fusion::PlanWalkable w(plan);
        bytes = w.memory_bytes();
        benchmark::DoNotOptimize(bytes);
    }
    state.counters["floor_bytes"] = static_cast<double>(bytes);
    state.counters["walls"] = static_cast<double>(plan.walls.size());
}
BENCHMARK(BM_PlanWalkableBuild)->Unit(benchmark::kMillisecond);

void BM_WalkFilterFix(benchmark::State& state) {
    if (!putmc_floor()) return state.SkipWithError("no PUTMC data");
    fusion::WalkFilterConfig cfg;
    cfg.particles = static_cast<int>(state.range(0));
    fusion::WalkFilter pf(putmc_floor(), cfg);
    pf.fix(kStart, Eigen::Matrix2d::Identity() * 4.0);
    for (auto _ : state) pf.fix({kStart.x + 1.0, kStart.y}, Eigen::Matrix2d::Identity() * 4.0);
}
BENCHMARK(BM_WalkFilterFix)->Arg(2000)->Unit(benchmark::kMicrosecond);

// Reading the estimate after a step: the weighted mean (arg 1 = 0) or the mode within 3 m that
// real walks use (arg 1 = 3; WalkFilterConfig::real_walks()), on a cloud spread by walking with
// fixes. The filter works the estimate out once per step and fix (its cost is in
// BM_WalkFilterStep and BM_WalkFilterFix), so this is the read alone.
void BM_WalkFilterEstimate(benchmark::State& state) {
    if (!putmc_floor()) return state.SkipWithError("no PUTMC data");
    fusion::WalkFilterConfig cfg;
    cfg.particles = static_cast<int>(state.range(0));
    cfg.estimate_radius_m = static_cast<double>(state.range(1));
    cfg.reseed_max_fraction = 0.7;
    fusion::WalkFilter pf(putmc_floor(), cfg);
    pf.fix(kStart, Eigen::Matrix2d::Identity() * 4.0);
    for (int n = 1; n <= 24; ++n) {
        pf.step(0.7, -1.5);
        if (n % 6 == 0) pf.fix({kStart.x + 0.5 * n, kStart.y}, Eigen::Matrix2d::Identity() * 4.0);
    }
    for (auto _ : state) benchmark::DoNotOptimize(pf.position());
}
BENCHMARK(BM_WalkFilterEstimate)->ArgsProduct({{2000}, {0, 3}})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
