// plan_from_image on the PUT Mobile Computing drawing (LOCUS_DATA_DIR/putmc/map/floorplan.png,
// 3049 × 1049 px at 28.4 px/m): the vectorising alone (the PNG is read once, outside the
// timing), and the walk grid the router then builds from the result. Counters: walls, wall
// points, space points. Skips with a message when the data folder is absent.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>

#include "image_file.hpp"
#include "locus/imaging/plan_from_image.hpp"
#include "locus/plan/walk_grid.hpp"
#include "build_paths.hpp"

namespace {

const std::string kDir = std::string(LOCUS_DATA_DIR) + "/putmc/map";

struct Drawing {
    locus::imaging::GreyImage image;
    double px_per_m = 0.0;
    bool ok = false;
};

const Drawing& drawing() {
    static const Drawing d = [] {
        Drawing out;
        if (!std::filesystem::exists(kDir + "/floorplan.png")) return out;
        out.image = locus::tools::read_grey_image(kDir + "/floorplan.png");
        std::ifstream(kDir + "/scale.map") >> out.px_per_m;
        out.ok = out.px_per_m > 0;
        return out;
    }();
    return d;
}

void BM_PlanFromImagePutmc(benchmark::State& state) {
    const auto& d = drawing();
    if (!d.ok) {
        state.SkipWithError((kDir + "/floorplan.png not found: the shared data folder is absent").c_str());
        return;
    }
    locus::imaging::FromImageOptions o;
    o.px_per_m = d.px_per_m;
    locus::imaging::FromImageStats stats;
    for (auto _ : state) benchmark::DoNotOptimize(locus::imaging::plan_from_image(d.image, o, &stats));
    state.counters["walls"] = static_cast<double>(stats.walls);
    state.counters["wall_points"] = static_cast<double>(stats.wall_points);
    state.counters["space_points"] = static_cast<double>(stats.space_points);
}
BENCHMARK(BM_PlanFromImagePutmc)->Unit(benchmark::kMillisecond);

void BM_WalkGridOfPutmcPlan(benchmark::State& state) {
    const auto& d = drawing();
    if (!d.ok) {
        state.SkipWithError((kDir + "/floorplan.png not found: the shared data folder is absent").c_str());
        return;
    }
    locus::imaging::FromImageOptions o;
    o.px_per_m = d.px_per_m;
    const auto plan = locus::imaging::plan_from_image(d.image, o);
    for (auto _ : state) benchmark::DoNotOptimize(locus::plan::build_walk_grid(plan));
}
BENCHMARK(BM_WalkGridOfPutmcPlan)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
