// "Where am I, in words" on a big floor (locus/floor_places.hpp): the room at a point and the
// POIs near it, what every answered position now costs on top. A floor of 1,000 rooms (one to
// three rectangles each) and 1,000 POIs on 200 m × 100 m, random points over it; against the
// plain scan of every room the answers used before (locus::room_at). Counters: the index's
// bytes.
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "locus/floor_places.hpp"

using namespace locus;

namespace {

struct Floor {
    std::vector<Room> rooms;
    std::vector<Poi> pois;
    std::vector<Point> points;
};

const Floor& big_floor() {
    static const Floor f = [] {
        Floor out;
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> x(0, 200), y(0, 100), side(2, 12);
        for (long long i = 1; i <= 1000; ++i) {
            Room r{i, "room " + std::to_string(i), {}};
            for (long long k = 0; k <= i % 3; ++k) {
                const double x0 = x(rng), y0 = y(rng);
                r.rects.push_back({x0, y0, x0 + side(rng), y0 + side(rng)});
            }
            out.rooms.push_back(std::move(r));
            out.pois.push_back({i, "poi " + std::to_string(i), "desk", {x(rng), y(rng)}});
        }
        for (int k = 0; k < 4096; ++k) out.points.push_back({x(rng), y(rng)});
        return out;
    }();
    return f;
}

void BM_RoomAt(benchmark::State& state) {
    const Floor& f = big_floor();
    const FloorPlaces places(f.rooms, f.pois);
    std::size_t k = 0;
    for (auto _ : state) benchmark::DoNotOptimize(places.room_at(f.points[k++ & 4095]));
    state.counters["index_bytes"] = static_cast<double>(places.memory_bytes());
}
BENCHMARK(BM_RoomAt);

// The scan of every room, as answers found the room before the index.
void BM_RoomAtScan(benchmark::State& state) {
    const Floor& f = big_floor();
    std::size_t k = 0;
    for (auto _ : state) benchmark::DoNotOptimize(room_at(f.rooms, f.points[k++ & 4095]));
}
BENCHMARK(BM_RoomAtScan);

void BM_Nearby(benchmark::State& state) {
    const Floor& f = big_floor();
    const FloorPlaces places(f.rooms, f.pois);
    std::size_t k = 0;
    for (auto _ : state) benchmark::DoNotOptimize(places.nearby(f.points[k++ & 4095]));
}
BENCHMARK(BM_Nearby);

void BM_Build(benchmark::State& state) {
    const Floor& f = big_floor();
    for (auto _ : state) benchmark::DoNotOptimize(FloorPlaces(f.rooms, f.pois));
}
BENCHMARK(BM_Build)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
