// Routing on a synthetic 3-floor building, 100 m × 100 m a floor: a 3 × 3 grid of 2 m
// corridors and 128 rooms of about 6 m × 12 m, each with a door onto a corridor (or onto the
// room between it and the corridor), two stairs and a lift on every floor. Measures the walk
// grid build of one floor and routes between random rooms across floors (each iteration one
// route; p50/p99/max CPU time of the single routes, and p99 wall time, are reported as
// counters), and the build of the whole
// building (grids and landmark distances). Run by hand:
//   build/bin/route_bench
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <random>
#include <time.h>

#include "locus/metrics.hpp"
#include "locus/plan/route.hpp"

namespace {

using namespace locus;
using namespace locus::plan;

constexpr double kSide = 100.0;
// Blocks between the corridors (lo, hi) along either axis; corridors fill the gaps.
constexpr double kBlocks[4][2] = {{0, 24}, {26, 49}, {51, 74}, {76, 100}};

Ring rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}; }

Plan synthetic_floor(std::int64_t below, std::int64_t above) {
    Plan p;
    for (int i = 0; i < 3; ++i) {
        const double lo = kBlocks[i][1], hi = kBlocks[i + 1][0];
        p.spaces.push_back({"Corridor H" + std::to_string(i), "corridor", {}, {rect(0, lo, kSide, hi), {}}, {}});
        p.spaces.push_back({"Corridor V" + std::to_string(i), "corridor", {}, {rect(lo, 0, hi, kSide), {}}, {}});
    }
    for (int bx = 0; bx < 4; ++bx)
        for (int by = 0; by < 4; ++by) {
            const double x0 = kBlocks[bx][0], x1 = kBlocks[bx][1], y0 = kBlocks[by][0], y1 = kBlocks[by][1];
            const double ym = (y0 + y1) / 2.0, w = (x1 - x0) / 4.0;
            for (int col = 0; col < 4; ++col)
                for (int row = 0; row < 2; ++row) {
                    const double rx0 = x0 + col * w, rx1 = rx0 + w, ry0 = row == 0 ? y0 : ym, ry1 = row == 0 ? ym : y1;
                    const Ring r = rect(rx0, ry0, rx1, ry1);
                    p.spaces.push_back({"Room " + std::to_string(p.spaces.size()), "room", {}, {r, {}}, {}});
                    p.walls.push_back({r});
                    // The door faces a corridor when one is there, else the room beside it.
                    const bool corridor_below = by > 0, corridor_above = by < 3;
                    const double door_y = row == 0 ? (corridor_below ? ry0 : ry1) : (corridor_above ? ry1 : ry0);
                    const Point at{(rx0 + rx1) / 2.0, door_y};
                    p.doors.push_back({at, at, ""});
                }
        }
    const auto add = [&](const std::string& id, ConnectorKind kind, Point at) {
        Connector c;
        c.id = id;
        c.name = id;
        c.kind = kind;
        c.at = at;
        c.step_free = kind == ConnectorKind::elevator;
        if (below >= 0) c.links.push_back({below, id});
        if (above >= 0) c.links.push_back({above, id});
        p.connectors.push_back(c);
    };
    add("stairs-sw", ConnectorKind::stairs, {25, 12});
    add("stairs-ne", ConnectorKind::stairs, {75, 88});
    add("lift", ConnectorKind::elevator, {50, 37});
    return p;
}

std::vector<FloorSpec> synthetic_building() {
    std::vector<FloorSpec> floors;
    for (int level = 0; level < 3; ++level)
        floors.push_back({level, level, synthetic_floor(level > 0 ? level - 1 : -1, level < 2 ? level + 1 : -1)});
    return floors;
}

const Building& building() {
    static const std::unique_ptr<Building> b = std::make_unique<Building>(build_building(synthetic_building()));
    return *b;
}

void BM_BuildFloorGrid(benchmark::State& state) {
    const Plan plan = synthetic_floor(-1, 1);
    for (auto _ : state) {
        WalkGrid g = build_walk_grid(plan);
        benchmark::DoNotOptimize(g);
    }
    const WalkGrid g = build_walk_grid(plan);
    state.counters["cells"] = g.cell_count();
    state.counters["free_cells"] = static_cast<double>(std::count_if(g.flags.begin(), g.flags.end(), [](auto f) { return f & WalkGrid::kFree; }));
}
BENCHMARK(BM_BuildFloorGrid)->Unit(benchmark::kMillisecond);

// Everything routing needs: three grids plus each floor's landmark distances.
void BM_BuildBuilding(benchmark::State& state) {
    const std::vector<FloorSpec> floors = synthetic_building();
    for (auto _ : state) {
        Building b = build_building(floors);
        benchmark::DoNotOptimize(b);
    }
    state.counters["floors"] = 3;
}
BENCHMARK(BM_BuildBuilding)->Unit(benchmark::kMillisecond);

// Room centres of a floor, for random endpoints.
std::vector<Point> room_centres(const Floor& f) {
    std::vector<Point> out;
    for (const Space& s : f.plan.spaces)
        if (s.kind == "room") {
            const Ring& r = s.shape.outer;
            out.push_back({(r[0].x + r[2].x) / 2.0, (r[0].y + r[2].y) / 2.0});
        }
    return out;
}

// from_level → to_level between random rooms; step_free optional.
void route_bench(benchmark::State& state, int from_level, int to_level, bool step_free) {
    const Building& b = building();
    const auto from_rooms = room_centres(b.floors[static_cast<std::size_t>(from_level)]);
    const auto to_rooms = room_centres(b.floors[static_cast<std::size_t>(to_level)]);
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::size_t> pick(0, from_rooms.size() - 1);
    RouteOptions o;
    o.step_free = step_free;
    // CPU time of this thread per route: the machine is shared, and the target is one core's work.
    const auto cpu_ms = [] {
        timespec t{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
        return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
    };
    std::vector<double> ms, wall_ms;
    double length = 0.0;
    std::size_t failed = 0;
    RouteScratch scratch;
    for (auto _ : state) {
        const Endpoint from{from_level, from_rooms[pick(rng)]}, to{to_level, to_rooms[pick(rng)]};
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = cpu_ms();
        const Route r = route(b, from, to, o, scratch);
        ms.push_back(cpu_ms() - c0);
        wall_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        length += r.length_m;
        failed += r.status != RouteStatus::ok;
        benchmark::DoNotOptimize(r);
    }
    std::sort(ms.begin(), ms.end());
    std::sort(wall_ms.begin(), wall_ms.end());
    // Percentiles as the load benches compute latency percentiles.
    state.counters["p50_ms"] = metrics::percentile_interpolated(ms, 0.50);
    state.counters["p99_ms"] = metrics::percentile_interpolated(ms, 0.99);
    state.counters["p99_wall_ms"] = metrics::percentile_interpolated(wall_ms, 0.99);
    state.counters["max_ms"] = ms.back();
    state.counters["mean_len_m"] = length / static_cast<double>(ms.size());
    state.counters["failed"] = static_cast<double>(failed);
}
BENCHMARK_CAPTURE(route_bench, same_floor, 0, 0, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(route_bench, level0_to_level2, 0, 2, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(route_bench, level0_to_level2_step_free, 0, 2, true)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
